#pragma once
// The paper's Fig. 8 (section 4) for one moment of a log, drawn with Cairo: one picture of eight
// panels, all in the odometry ("global") frame the pipeline works in, centred on the robot, at
// one scale, with the true obstacles drawn faintly beneath:
//   a  Radar Map (RADAR_MAP)                      b  hypothetical sonar scan (SONAR_HYPOTHESIS)
//   c  real sonar scan (SONAR_RING)               d  complementary readings (SONAR_COMPLEMENT)
//   e  operational AGM (AGM_OPERATIONAL)          e' tactical AGM (AGM_TACTICAL, AGM_LINES)
//   f  Current Sensor Map (CURRENT_SENSOR_MAP)    g  Sector Map (SECTOR_MAP)
// A panel whose channel is missing, or whose message is invalid, says so instead.
#include <cairo.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "render/snapshot.hpp"
#include "sim/scenario.hpp"

namespace lasonic::render {

class RenderError : public std::runtime_error {
 public:
  explicit RenderError(const std::string& w) : std::runtime_error(w) {}
};

struct RenderOptions {
  int panel_px = 400;   // each panel is a square of this many pixels
  double view_m = 7.0;  // [m] ground shown across a panel: the sonar's 3 m reach on every side
};

// What a panel shows: its data (drawn) or why not (note).
struct PanelStatus {
  std::string letter;   // the paper's Fig. 8 letter
  std::string title;
  std::string channel;
  bool drawn = false;
  std::string note;     // drawn: a summary ("18 segments, 0.12 s old"); else why not
};

struct ImageSize {
  int width = 0, height = 0;
};
ImageSize fig8Size(const RenderOptions& o);
// Throws RenderError naming the option if it is out of range.
void checkOptions(const RenderOptions& o);

// World (odometry frame, metres, y up) -> pixel mapping of one panel.
struct PanelView {
  double x0 = 0, y0 = 0;  // top-left pixel of the panel
  double size = 0;        // panel size [px]
  geom::Vec2 centre = geom::Vec2::Zero();  // world point at the panel's centre
  double px_per_m = 1;
  geom::Vec2 toPixel(const geom::Vec2& w) const {
    return {x0 + 0.5 * size + (w.x() - centre.x()) * px_per_m,
            y0 + 0.5 * size - (w.y() - centre.y()) * px_per_m};
  }
};
constexpr int kPanels = 8;
PanelView panelView(int index, const geom::Vec2& centre, const RenderOptions& o);

// Draws the figure onto cr, whose target has fig8Size(o). scenario may be null (no truth drawn).
std::vector<PanelStatus> drawFig8(cairo_t* cr, const Snapshot& s, const sim::Scenario* scenario,
                                  const RenderOptions& o);

// Draws into a new image and writes it as PNG. Throws RenderError if it cannot be written.
std::vector<PanelStatus> writeFig8Png(const std::string& path, const Snapshot& s,
                                      const sim::Scenario* scenario, const RenderOptions& o);

// Frees the process-wide caches of Cairo and of fontconfig (which Cairo's text uses). Call once
// at exit, after all drawing: a leak checker (the sanitizer build) then reports only our own.
void releaseStaticData();

}  // namespace lasonic::render
