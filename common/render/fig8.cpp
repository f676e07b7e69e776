#include "render/fig8.hpp"

#include <fontconfig/fontconfig.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

#include "core/pose_msg.hpp"
#include "lcmio/node.hpp"

namespace lasonic::render {

namespace {

constexpr int kHeaderPx = 30;
constexpr int kLegendPx = 48;
constexpr double kMaxRange = 100.0;  // [m] a beam or distance beyond this is not drawable

// ------------------------------------------------------------------------------ colours
struct Rgba {
  double r, g, b, a;
};
namespace colour {
constexpr Rgba kTruth{0.55, 0.55, 0.55, 0.45};
constexpr Rgba kTruthInvisible{0.55, 0.25, 0.75, 0.40};  // laser-invisible material
constexpr Rgba kRobot{0.10, 0.10, 0.10, 0.90};
constexpr Rgba kLaser{0.12, 0.37, 0.75, 1.0};
constexpr Rgba kHypothesis{0.17, 0.60, 0.17, 1.0};
constexpr Rgba kEcho{0.20, 0.20, 0.20, 1.0};
constexpr Rgba kComplementary{0.93, 0.47, 0.0, 1.0};
constexpr Rgba kRedundant{0.50, 0.50, 0.50, 1.0};
constexpr Rgba kFalse{0.84, 0.15, 0.16, 1.0};
constexpr Rgba kAgmWeight{0.98, 0.62, 0.25, 1.0};
constexpr Rgba kAgmOccupied{0.55, 0.22, 0.0, 1.0};
// ... a tactical cell only echoes the laser could not check made (grid_map_t::heard): the pilot
// does not remember it (README "Method, as implemented", step 5); lcm-spy's grid plugin's colour.
constexpr Rgba kAgmUnchecked{0.47, 0.43, 0.63, 1.0};
constexpr Rgba kSonarLine{0.85, 0.33, 0.0, 1.0};
constexpr Rgba kSonarCopied{0.98, 0.75, 0.45, 1.0};
constexpr Rgba kRemembered{0.55, 0.27, 0.65, 1.0};  // the tactical memory (purple)
constexpr Rgba kText{0.10, 0.10, 0.10, 1.0};
constexpr Rgba kNote{0.45, 0.45, 0.45, 1.0};
constexpr Rgba kStale{0.84, 0.10, 0.10, 1.0};
}  // namespace colour

void set(cairo_t* cr, const Rgba& c, double alpha = 1.0) { cairo_set_source_rgba(cr, c.r, c.g, c.b, c.a * alpha); }

bool finite(double v) { return std::isfinite(v); }
bool finite(const geom::Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }
bool finite(const geom::Pose2& p) { return finite(p.x) && finite(p.y) && finite(p.theta); }

// A pixel position Cairo can take (its fixed point covers about +-8e6).
bool drawable(const geom::Vec2& px) { return finite(px) && std::abs(px.x()) < 1e6 && std::abs(px.y()) < 1e6; }

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string age(int64_t msg_utime, int64_t now) {
  return fmt("%.2f s old", static_cast<double>(now - msg_utime) * 1e-6);
}

// ------------------------------------------------------------------------------ text
void font(cairo_t* cr, double size, bool bold = false) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
}

double textWidth(cairo_t* cr, const std::string& s) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

// Splits s after ", " or "; " into lines no wider than width (in the current font).
std::vector<std::string> wrap(cairo_t* cr, const std::string& s, double width) {
  std::vector<std::string> words;
  size_t start = 0;
  for (size_t i = 0; i + 1 < s.size(); ++i)
    if ((s[i] == ',' || s[i] == ';' || s[i] == ':') && s[i + 1] == ' ') {
      words.push_back(s.substr(start, i + 2 - start));
      start = i + 2;
    }
  words.push_back(s.substr(start));
  std::vector<std::string> lines{""};
  for (const auto& w : words) {
    if (!lines.back().empty() && textWidth(cr, lines.back() + w) > width) lines.emplace_back();
    lines.back() += w;
  }
  return lines;
}

void text(cairo_t* cr, double x, double y, const std::string& s) {
  cairo_move_to(cr, x, y);
  cairo_show_text(cr, s.c_str());
}

// ------------------------------------------------------------------------------ primitives
void line(cairo_t* cr, const PanelView& v, const geom::Vec2& a, const geom::Vec2& b) {
  const auto pa = v.toPixel(a), pb = v.toPixel(b);
  if (!drawable(pa) || !drawable(pb)) return;
  cairo_move_to(cr, pa.x(), pa.y());
  cairo_line_to(cr, pb.x(), pb.y());
}

// Pixel-space angle of a world heading (y is flipped).
double screenAngle(double world) { return -world; }

// Circular sector (a beam) of a sensor at `pose` with full opening `width` and radius `r`.
bool wedgePath(cairo_t* cr, const PanelView& v, const geom::Pose2& pose, double width, double r) {
  const auto c = v.toPixel(pose.position());
  if (!drawable(c) || !finite(width) || !finite(r) || r < 0 || r > kMaxRange) return false;
  cairo_move_to(cr, c.x(), c.y());
  cairo_arc(cr, c.x(), c.y(), r * v.px_per_m, screenAngle(pose.theta + width / 2), screenAngle(pose.theta - width / 2));
  cairo_close_path(cr);
  return true;
}

// The arc of that sector only (where the echo lies).
bool arcPath(cairo_t* cr, const PanelView& v, const geom::Pose2& pose, double width, double r) {
  const auto c = v.toPixel(pose.position());
  if (!drawable(c) || !finite(width) || !finite(r) || r < 0 || r > kMaxRange) return false;
  cairo_new_sub_path(cr);
  cairo_arc(cr, c.x(), c.y(), r * v.px_per_m, screenAngle(pose.theta + width / 2), screenAngle(pose.theta - width / 2));
  return true;
}

bool validBeam(const SonarBeam& b) {
  return finite(b.pose) && finite(b.beam_width) && b.beam_width > 0 && b.beam_width < geom::kPi &&
         finite(b.range) && b.range >= 0 && b.range <= kMaxRange;
}

// ------------------------------------------------------------------------------ layers
void drawTruth(cairo_t* cr, const PanelView& v, const Snapshot& s, const sim::Scenario* sc) {
  const auto odom_from_true = s.odomFromTrue();
  if (!odom_from_true || !finite(*odom_from_true)) return;
  const auto& T = *odom_from_true;
  cairo_save(cr);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_width(cr, 3.0);
  if (sc) {
    for (const auto& p : sc->statics) {
      set(cr, sc->laserVisible(p.obstacle) ? colour::kTruth : colour::kTruthInvisible);
      if (p.kind == sim::Primitive::Kind::Segment) {
        line(cr, v, T.transform(p.segment.a), T.transform(p.segment.b));
      } else {
        const auto c = v.toPixel(T.transform(p.circle.center));
        if (!drawable(c)) continue;
        cairo_new_sub_path(cr);
        cairo_arc(cr, c.x(), c.y(), std::max(1.0, p.circle.radius * v.px_per_m), 0, 2 * geom::kPi);
      }
      cairo_stroke(cr);
    }
  }
  // Movers (people): their true outline now.
  for (const auto& m : s.movers) {
    const auto c = v.toPixel(T.transform(m.position));
    if (!drawable(c) || !finite(m.radius) || m.radius <= 0 || m.radius > kMaxRange) continue;
    set(cr, colour::kTruth, 0.5);
    cairo_new_sub_path(cr);
    cairo_arc(cr, c.x(), c.y(), m.radius * v.px_per_m, 0, 2 * geom::kPi);
    cairo_fill_preserve(cr);
    set(cr, colour::kTruth);
    cairo_stroke(cr);
  }
  cairo_restore(cr);
}

void drawRobot(cairo_t* cr, const PanelView& v, const geom::Pose2& pose, double radius) {
  if (!finite(pose)) return;
  const auto c = v.toPixel(pose.position());
  if (!drawable(c)) return;
  cairo_save(cr);
  set(cr, colour::kRobot);
  cairo_set_line_width(cr, 1.5);
  cairo_new_sub_path(cr);
  cairo_arc(cr, c.x(), c.y(), radius * v.px_per_m, 0, 2 * geom::kPi);
  cairo_stroke(cr);
  line(cr, v, pose.position(), pose.transform({radius, 0}));
  cairo_stroke(cr);
  cairo_restore(cr);
}

// Segments of a line map; returns the number drawn and counts invalid ones.
int drawLines(cairo_t* cr, const PanelView& v, const line_map_t& m, double width, int& invalid,
              double alpha = 1.0, bool by_source = true) {
  int n = 0;
  cairo_save(cr);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_width(cr, width);
  for (const auto& sg : m.segments) {
    const geom::Vec2 a(sg.x0, sg.y0), b(sg.x1, sg.y1);
    if (!finite(a) || !finite(b) || (b - a).norm() > 1e3) {
      ++invalid;
      continue;
    }
    if (!by_source || sg.source == line_segment_t::SOURCE_LASER) set(cr, colour::kLaser, alpha);
    else if (sg.source == line_segment_t::SOURCE_SONAR) set(cr, colour::kSonarLine, alpha);
    else {
      ++invalid;
      continue;
    }
    line(cr, v, a, b);
    cairo_stroke(cr);
    ++n;
  }
  cairo_restore(cr);
  return n;
}

// Why a grid map cannot be drawn, or "" if it can.
std::string gridProblem(const grid_map_t& g) {
  if (g.width <= 0 || g.height <= 0) return "width/height must be > 0";
  if (static_cast<int64_t>(g.width) * g.height != g.ncells)
    return "ncells " + std::to_string(g.ncells) + " != width*height";
  if (g.g.size() != static_cast<size_t>(g.ncells) || g.gp.size() != static_cast<size_t>(g.ncells))
    return "arrays do not hold ncells values";
  if (!finite(g.cell_size) || g.cell_size <= 0 || g.cell_size > 100) return "cell_size out of range";
  if (!finite(g.origin_x) || !finite(g.origin_y)) return "origin not finite";
  return "";
}

bool occupied(const grid_map_t& g, size_t i) { return g.gp[i] > 0 && g.gp[i] >= g.gp_threshold; }

// Only echoes the laser could not check made the cell (a map without the record: none).
bool uncheckedOnly(const grid_map_t& g, size_t i) {
  return g.heard.size() == g.g.size() && g.heard[i] == grid_map_t::HEARD_UNCHECKED;
}

struct GridCounts {
  int occupied = 0;   // in view, Gp >= the map's threshold
  int unchecked = 0;  // ... of them only echoes the laser could not check made
};

// AGM cells: light for G > 0 (weight as opacity), dark for Gp >= the map's threshold.
// `frame`: the view's frame <- the grid's (a map in another global frame), if any.
GridCounts drawGrid(cairo_t* cr, const PanelView& v, const grid_map_t& g, const std::optional<geom::Pose2>& frame = {}) {
  // A rotated grid: every cell a quadrangle, the range of cells a bit wider.
  const double half = 0.5 * v.size / v.px_per_m * (frame ? 1.5 : 1.0);
  const geom::Vec2 centre = frame ? frame->inverseTransform(v.centre) : v.centre;
  const double cs = g.cell_size;
  auto clampIdx = [](double f, int n) { return static_cast<int>(std::clamp(f, 0.0, static_cast<double>(n - 1))); };
  const int ix0 = clampIdx(std::floor((centre.x() - half - g.origin_x) / cs), g.width);
  const int ix1 = clampIdx(std::floor((centre.x() + half - g.origin_x) / cs), g.width);
  const int iy0 = clampIdx(std::floor((centre.y() - half - g.origin_y) / cs), g.height);
  const int iy1 = clampIdx(std::floor((centre.y() + half - g.origin_y) / cs), g.height);
  auto quad = [&](double x0, double y0, double w, double h) {  // grid-frame rectangle -> path
    const geom::Vec2 c[4] = {{x0, y0}, {x0 + w, y0}, {x0 + w, y0 + h}, {x0, y0 + h}};
    for (int k = 0; k < 4; ++k) {
      const geom::Vec2 q = v.toPixel(frame ? frame->transform(c[k]) : c[k]);
      if (k == 0) cairo_move_to(cr, q.x(), q.y());
      else cairo_line_to(cr, q.x(), q.y());
    }
    cairo_close_path(cr);
  };
  GridCounts n;
  cairo_save(cr);
  for (int pass = 0; pass < 2; ++pass) {  // weights first, occupied cells on top
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix) {
        const size_t i = static_cast<size_t>(iy) * static_cast<size_t>(g.width) + static_cast<size_t>(ix);
        const bool occ = occupied(g, i);
        if (pass == 0 ? (g.g[i] <= 0 || occ) : !occ) continue;
        const geom::Vec2 corner{g.origin_x + ix * cs, g.origin_y + (iy + 1) * cs};
        const auto p = v.toPixel(frame ? frame->transform(corner) : corner);
        if (!drawable(p)) continue;
        if (occ) {
          const bool unchecked = uncheckedOnly(g, i);
          set(cr, unchecked ? colour::kAgmUnchecked : colour::kAgmOccupied);
          ++n.occupied;
          n.unchecked += unchecked ? 1 : 0;
        } else {
          set(cr, colour::kAgmWeight, 0.25 + 0.5 * std::min(1.0, g.g[i] / 4.0));
        }
        if (frame) quad(g.origin_x + ix * cs, g.origin_y + iy * cs, cs, cs);
        else cairo_rectangle(cr, p.x(), p.y(), cs * v.px_per_m, cs * v.px_per_m);
        cairo_fill(cr);
      }
  }
  // The window's outline: the AGM is local and follows the robot (section 3.2).
  const auto a = v.toPixel({g.origin_x, g.origin_y + g.height * cs});
  if (drawable(a)) {
    cairo_set_line_width(cr, 1.0);
    const double dash[] = {4.0, 4.0};
    cairo_set_dash(cr, dash, 2, 0);
    set(cr, colour::kNote, 0.8);
    if (frame) quad(g.origin_x, g.origin_y, g.width * cs, g.height * cs);
    else cairo_rectangle(cr, a.x(), a.y(), g.width * cs * v.px_per_m, g.height * cs * v.px_per_m);
    cairo_stroke(cr);
  }
  cairo_restore(cr);
  return n;
}

// ------------------------------------------------------------------------------ panels
struct Panel {
  PanelStatus status;
  PanelView view;
  std::vector<std::string> flags;  // red remarks (stale sensors)
};

void missing(Panel& p, const Snapshot& s, const std::string& channel) {
  p.status.drawn = false;
  p.status.note = s.in_log.count(channel) ? "no " + channel + " yet at this time" : "no " + channel + " in log";
}

void invalid(Panel& p, const std::string& channel, const std::string& why) {
  p.status.drawn = false;
  p.status.note = "invalid " + channel + " message: " + why;
}

void panelRadarMap(cairo_t* cr, Panel& p, const Snapshot& s) {
  if (!s.radar_map) return missing(p, s, channels::RADAR_MAP);
  int bad = 0;
  const int n = drawLines(cr, p.view, *s.radar_map, 2.5, bad, 1.0, false);
  p.status.drawn = true;
  p.status.note = std::to_string(n) + " segments, " + age(s.radar_map->utime, s.utime);
  if (bad) p.status.note += ", " + std::to_string(bad) + " invalid skipped";
}

void panelHypothesis(cairo_t* cr, Panel& p, const Snapshot& s) {
  if (s.hypothesis.empty()) return missing(p, s, channels::SONAR_HYPOTHESIS);
  // The Radar Map it was computed on, faintly.
  int bad = 0;
  if (s.radar_map) drawLines(cr, p.view, *s.radar_map, 1.5, bad, 0.35, false);
  int n = 0, at_limit = 0;
  cairo_save(cr);
  cairo_set_line_width(cr, 1.2);
  for (const auto& b : s.hypothesis) {
    if (!validBeam(b)) continue;
    if (!wedgePath(cr, p.view, b.pose, b.beam_width, b.range)) continue;
    set(cr, colour::kHypothesis, 0.16);
    cairo_fill_preserve(cr);
    set(cr, colour::kHypothesis, 0.7);
    cairo_stroke(cr);
    ++n;
    if (b.range >= s.hypothesis_limit - 1e-3) ++at_limit;
  }
  cairo_restore(cr);
  p.status.drawn = true;
  p.status.note = std::to_string(n) + " sensors, " + std::to_string(at_limit) + " at the " +
                  fmt("%.2f m limit", s.hypothesis_limit);
}

void panelSonar(cairo_t* cr, Panel& p, const Snapshot& s) {
  if (s.sonar.empty()) {
    missing(p, s, channels::SONAR_RING);
    if (s.sonar_unplaced > 0) p.status.note = "SONAR_RING without ODOMETRY or SONAR_HYPOTHESIS to place it";
    return;
  }
  int echoes = 0, silent = 0;
  cairo_save(cr);
  for (const auto& b : s.sonar) {
    if (!validBeam(b)) continue;
    if (b.echo) {
      if (!wedgePath(cr, p.view, b.pose, b.beam_width, b.range)) continue;
      set(cr, colour::kEcho, 0.08);
      cairo_fill(cr);
      if (!arcPath(cr, p.view, b.pose, b.beam_width, b.range)) continue;
      set(cr, colour::kEcho, 0.9);
      cairo_set_line_width(cr, 2.0);
      cairo_stroke(cr);
      ++echoes;
    } else {
      // No echo: where the beam ends (range_max), dotted.
      if (!arcPath(cr, p.view, b.pose, b.beam_width, b.range)) continue;
      const double dash[] = {2.0, 3.0};
      cairo_set_dash(cr, dash, 2, 0);
      set(cr, colour::kEcho, 0.35);
      cairo_set_line_width(cr, 1.0);
      cairo_stroke(cr);
      cairo_set_dash(cr, nullptr, 0, 0);
      ++silent;
    }
  }
  cairo_restore(cr);
  p.status.drawn = true;
  p.status.note = std::to_string(echoes) + " echoes, " + std::to_string(silent) + " without echo";
}

void panelComplement(cairo_t* cr, Panel& p, const Snapshot& s) {
  if (s.complement.empty()) return missing(p, s, channels::SONAR_COMPLEMENT);
  int comp = 0, redundant = 0, false_ = 0;
  cairo_save(cr);
  for (const auto& b : s.complement) {
    if (!validBeam(b)) continue;
    switch (b.cls) {
      case complement_reading_t::CLASS_OUTSIDE_VIEW:  // used as complementary (beyond the laser's view)
      case complement_reading_t::CLASS_COMPLEMENTARY:
        if (!wedgePath(cr, p.view, b.pose, b.beam_width, b.range)) break;
        set(cr, colour::kComplementary, 0.30);
        cairo_fill(cr);
        if (!arcPath(cr, p.view, b.pose, b.beam_width, b.range)) break;
        set(cr, colour::kComplementary);
        cairo_set_line_width(cr, 2.5);
        cairo_stroke(cr);
        ++comp;
        break;
      case complement_reading_t::CLASS_SEEN_BEFORE:  // redundant on lines an earlier scan saw there
      case complement_reading_t::CLASS_REDUNDANT:
        if (!arcPath(cr, p.view, b.pose, b.beam_width, b.range)) break;
        set(cr, colour::kRedundant, 0.8);
        cairo_set_line_width(cr, 1.0);
        cairo_stroke(cr);
        ++redundant;
        break;
      case complement_reading_t::CLASS_FALSE: {
        if (!arcPath(cr, p.view, b.pose, b.beam_width, b.range)) break;
        const double dash[] = {4.0, 3.0};
        cairo_set_dash(cr, dash, 2, 0);
        set(cr, colour::kFalse, 0.9);
        cairo_set_line_width(cr, 1.2);
        cairo_stroke(cr);
        cairo_set_dash(cr, nullptr, 0, 0);
        ++false_;
        break;
      }
      default: break;  // unverifiable / invalid: nothing to show
    }
  }
  cairo_restore(cr);
  p.status.drawn = true;
  p.status.note = std::to_string(comp) + " complementary, " + std::to_string(redundant) + " redundant, " +
                  std::to_string(false_) + " false";
}

// frame: the odometry frame <- the grid's (Snapshot::agm_tactical_frame), if they differ.
void panelGrid(cairo_t* cr, Panel& p, const Snapshot& s, const std::optional<grid_map_t>& g,
               const std::string& channel, const std::optional<line_map_t>* lines,
               const std::optional<geom::Pose2>& frame = std::nullopt) {
  if (!g) return missing(p, s, channel);
  const auto why = gridProblem(*g);
  if (!why.empty()) return invalid(p, channel, why);
  const GridCounts occ = drawGrid(cr, p.view, *g, frame);
  p.status.drawn = true;
  p.status.note = std::to_string(g->width) + "x" + std::to_string(g->height) + " cells of " +
                  fmt("%.2f m", g->cell_size) + ", " + std::to_string(occ.occupied) + " in view with Gp >= " +
                  std::to_string(g->gp_threshold);
  if (occ.unchecked > 0)
    p.status.note += " (" + std::to_string(occ.unchecked) + " only echoes the laser could not check made)";
  p.status.note += ", " + age(g->utime, s.utime);
  if (lines) {
    if (*lines) {
      int bad = 0;
      const int n = drawLines(cr, p.view, **lines, 2.5, bad);
      p.status.note += "; " + std::to_string(n) + " AGM_LINES";
    } else {
      p.status.note += s.in_log.count(channels::AGM_LINES) ? "; no AGM_LINES yet" : "; no AGM_LINES in log";
    }
  }
}

void panelCsm(cairo_t* cr, Panel& p, const Snapshot& s) {
  if (!s.current_sensor_map) return missing(p, s, channels::CURRENT_SENSOR_MAP);
  int bad = 0, laser = 0, sonar = 0;
  for (const auto& sg : s.current_sensor_map->segments) {
    if (sg.source == line_segment_t::SOURCE_LASER) ++laser;
    else if (sg.source == line_segment_t::SOURCE_SONAR) ++sonar;
  }
  drawLines(cr, p.view, *s.current_sensor_map, 2.5, bad);
  p.status.drawn = true;
  p.status.note = std::to_string(laser) + " laser + " + std::to_string(sonar) + " sonar lines, " +
                  age(s.current_sensor_map->utime, s.utime);
  if (bad) p.status.note += ", " + std::to_string(bad) + " invalid skipped";
}

void panelSectorMap(cairo_t* cr, Panel& p, const Snapshot& s) {
  if (!s.sector_map) return missing(p, s, channels::SECTOR_MAP);
  const sector_map_t& m = *s.sector_map;
  const auto pose = toPose(m.robot_pose);
  if (m.nsectors <= 0 || m.nsectors > 3600) return invalid(p, channels::SECTOR_MAP, "nsectors out of range");
  if (!finite(pose)) return invalid(p, channels::SECTOR_MAP, "robot_pose not finite");
  const double R = (finite(m.robot_radius) && m.robot_radius > 0 && m.robot_radius < 10) ? m.robot_radius : s.robot_radius;
  const auto c = p.view.toPixel(pose.position());
  const double w = 2 * geom::kPi / m.nsectors;
  int counts[5] = {0, 0, 0, 0, 0};
  cairo_save(cr);
  // The reach: obstacles beyond max_range from the boundary are not reported.
  if (drawable(c) && finite(m.max_range) && m.max_range > 0 && m.max_range < kMaxRange) {
    set(cr, colour::kNote, 0.5);
    cairo_set_line_width(cr, 1.0);
    const double dash[] = {3.0, 3.0};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_new_sub_path(cr);
    cairo_arc(cr, c.x(), c.y(), (R + m.max_range) * p.view.px_per_m, 0, 2 * geom::kPi);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
  }
  for (int k = 0; k < m.nsectors && drawable(c); ++k) {
    const double d = m.distance[k];
    const int src = m.source[k];
    if (!finite(d) || d < 0 || d > kMaxRange) continue;
    const double a0 = pose.theta - geom::kPi + k * w, a1 = a0 + w;
    const double r0 = R * p.view.px_per_m, r1 = (R + d) * p.view.px_per_m;
    cairo_new_path(cr);
    cairo_arc(cr, c.x(), c.y(), r1, screenAngle(a1), screenAngle(a0));
    cairo_arc_negative(cr, c.x(), c.y(), r0, screenAngle(a0), screenAngle(a1));
    cairo_close_path(cr);
    switch (src) {
      case sector_map_t::SOURCE_LASER: set(cr, colour::kLaser, 0.55); break;
      case sector_map_t::SOURCE_SONAR: set(cr, colour::kComplementary, 0.75); break;
      case sector_map_t::SOURCE_SONAR_COPIED: set(cr, colour::kSonarCopied, 0.85); break;
      case sector_map_t::SOURCE_REMEMBERED: set(cr, colour::kRemembered, 0.6); break;
      default: set(cr, colour::kNote, 0.4); break;
    }
    cairo_fill_preserve(cr);
    set(cr, colour::kText, 0.35);
    cairo_set_line_width(cr, 0.6);
    cairo_stroke(cr);
    if (src >= 0 && src < 5) ++counts[src];
  }
  cairo_restore(cr);
  p.status.drawn = true;
  p.status.note = std::to_string(counts[1]) + " laser, " + std::to_string(counts[2]) + " sonar, " +
                  std::to_string(counts[3]) + " copied, " + std::to_string(counts[4]) + " remembered of " +
                  std::to_string(m.nsectors) + " sectors";
  auto sensor = [](const char* name, int8_t stale, float age_s) {
    std::string f = name;
    if (age_s < 0) return f + " never";
    return f + (stale ? " STALE " : " ") + fmt("%.2f s", age_s);
  };
  if (m.laser_stale || m.laser_age_s < 0) p.flags.push_back(sensor("laser", m.laser_stale, m.laser_age_s));
  if (m.sonar_stale || m.sonar_age_s < 0) p.flags.push_back(sensor("sonar", m.sonar_stale, m.sonar_age_s));
}

// ------------------------------------------------------------------------------ frame
double niceLength(double target) {
  const double e = std::pow(10.0, std::floor(std::log10(target)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * e >= target) return m * e;
  return 10 * e;
}

void drawScaleBar(cairo_t* cr, const PanelView& v) {
  const double len_m = niceLength(v.size / v.px_per_m / 6.0);
  const double len = len_m * v.px_per_m;
  const double x = v.x0 + 12, y = v.y0 + v.size - 14;
  cairo_save(cr);
  set(cr, colour::kText);
  cairo_set_line_width(cr, 2.0);
  cairo_move_to(cr, x, y - 4);
  cairo_line_to(cr, x, y);
  cairo_line_to(cr, x + len, y);
  cairo_line_to(cr, x + len, y - 4);
  cairo_stroke(cr);
  font(cr, 11);
  text(cr, x + len + 5, y + 1, len_m >= 1 ? fmt("%.0f m", len_m) : fmt("%.1f m", len_m));
  // Frame axes (the panels are in the odometry frame, not the robot's).
  const double ax = v.x0 + v.size - 30, ay = y;
  cairo_set_line_width(cr, 1.2);
  cairo_move_to(cr, ax, ay);
  cairo_line_to(cr, ax + 18, ay);
  cairo_move_to(cr, ax, ay);
  cairo_line_to(cr, ax, ay - 18);
  cairo_stroke(cr);
  font(cr, 10);
  text(cr, ax + 20, ay + 3, "x");
  text(cr, ax - 3, ay - 21, "y");
  cairo_restore(cr);
}

void drawPanelFrame(cairo_t* cr, const Panel& p) {
  const auto& v = p.view;
  cairo_save(cr);
  font(cr, 10.5);
  const auto sub = wrap(cr, p.status.channel + (p.status.drawn ? ": " + p.status.note : ""), v.size - 16);
  // Title strip, translucent so the data beneath stays visible.
  cairo_set_source_rgba(cr, 1, 1, 1, 0.8);
  cairo_rectangle(cr, v.x0, v.y0, v.size, 22 + 14 * static_cast<double>(sub.size()));
  cairo_fill(cr);
  set(cr, colour::kText);
  font(cr, 14, true);
  text(cr, v.x0 + 8, v.y0 + 16, p.status.letter + "  " + p.status.title);
  font(cr, 10.5);
  set(cr, p.status.drawn ? colour::kNote : colour::kStale);
  for (size_t i = 0; i < sub.size(); ++i) text(cr, v.x0 + 8, v.y0 + 31 + 14 * static_cast<double>(i), sub[i]);
  if (!p.status.drawn) {
    font(cr, 13);
    set(cr, colour::kNote);
    double y = v.y0 + 0.5 * v.size + 40;
    for (const auto& l : wrap(cr, p.status.note, v.size - 16)) {
      text(cr, v.x0 + std::max(8.0, 0.5 * (v.size - textWidth(cr, l))), y, l);
      y += 17;
    }
  }
  double fy = v.y0 + 38 + 14 * static_cast<double>(sub.size());
  for (const auto& f : p.flags) {
    font(cr, 12, true);
    set(cr, colour::kStale);
    text(cr, v.x0 + v.size - 8 - textWidth(cr, f), fy, f);
    fy += 16;
  }
  drawScaleBar(cr, v);
  // Border.
  cairo_set_source_rgb(cr, 0.75, 0.75, 0.75);
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr, v.x0 + 0.5, v.y0 + 0.5, v.size - 1, v.size - 1);
  cairo_stroke(cr);
  cairo_restore(cr);
}

void drawHeader(cairo_t* cr, const Snapshot& s, const sim::Scenario* sc, const RenderOptions& o) {
  const auto size = fig8Size(o);
  cairo_save(cr);
  cairo_set_source_rgb(cr, 0.95, 0.95, 0.95);
  cairo_rectangle(cr, 0, 0, size.width, kHeaderPx);
  cairo_fill(cr);
  set(cr, colour::kText);
  font(cr, 14, true);
  std::string h = s.log_name.empty() ? "lasonic" : s.log_name;
  h += fmt("   t = %.2f s", s.t_s) + fmt(" of %.2f s", s.duration_s);
  text(cr, 10, 20, h);
  double x = 10 + textWidth(cr, h) + 20;
  font(cr, 12);
  std::string r;
  if (s.robot && finite(*s.robot))
    r = "robot (odometry frame) " + fmt("x %.2f", s.robot->x) + fmt(" y %.2f m", s.robot->y) +
        fmt("  heading %.1f deg", geom::rad2deg(s.robot->theta));
  else
    r = "robot pose unknown";
  std::string truth;
  if (!s.odomFromTrue()) truth = "truth: none (no SIM_STATE or ODOMETRY)";
  else if (!sc) truth = "truth: movers only (no --scenario)";
  else truth = "truth: scenario " + sc->name + " (faint)";
  // What does not fit is left out, the citation first.
  const std::string cite = "panels as Jörg 1995, Fig. 8";
  std::string info = r + "     " + truth;
  if (x + textWidth(cr, info) > size.width - 10) info = r;
  text(cr, x, 20, info);
  x += textWidth(cr, info) + 30;
  if (x + textWidth(cr, cite) < size.width - 10) text(cr, size.width - 10 - textWidth(cr, cite), 20, cite);
  cairo_restore(cr);
}

enum class Swatch { Line, Dashed, Fill, Wedge };
struct LegendItem {
  Swatch kind;
  Rgba c;
  double alpha;
  std::string label;
};

void drawLegend(cairo_t* cr, const RenderOptions& o) {
  const auto size = fig8Size(o);
  const double y0 = size.height - kLegendPx;
  cairo_save(cr);
  cairo_set_source_rgb(cr, 0.95, 0.95, 0.95);
  cairo_rectangle(cr, 0, y0, size.width, kLegendPx);
  cairo_fill(cr);
  const std::vector<std::vector<LegendItem>> rows = {
      {{Swatch::Line, colour::kTruth, 1, "true obstacle"},
       {Swatch::Line, colour::kTruthInvisible, 1, "true obstacle, laser-invisible"},
       {Swatch::Line, colour::kLaser, 1, "laser line (Radar Map)"},
       {Swatch::Wedge, colour::kHypothesis, 0.3, "hypothetical reading"},
       {Swatch::Line, colour::kEcho, 1, "sonar echo"},
       {Swatch::Dashed, colour::kEcho, 0.5, "no echo"},
       {Swatch::Wedge, colour::kComplementary, 0.5, "complementary"},
       {Swatch::Line, colour::kRedundant, 1, "redundant"},
       {Swatch::Dashed, colour::kFalse, 1, "false (specular)"}},
      {{Swatch::Fill, colour::kAgmWeight, 0.6, "AGM cell, G > 0"},
       {Swatch::Fill, colour::kAgmOccupied, 1, "AGM cell, Gp >= threshold"},
       {Swatch::Fill, colour::kAgmUnchecked, 1, "... only unchecked echoes"},
       {Swatch::Line, colour::kSonarLine, 1, "sonar line (tactical AGM)"},
       {Swatch::Fill, colour::kLaser, 0.55, "sector: laser"},
       {Swatch::Fill, colour::kComplementary, 0.75, "sector: sonar"},
       {Swatch::Fill, colour::kSonarCopied, 0.85, "sector: sonar, copied"},
       {Swatch::Fill, colour::kRemembered, 0.6, "sector: remembered"},
       {Swatch::Line, colour::kRobot, 1, "robot (odometry pose)"}},
  };
  font(cr, 11);
  for (size_t r = 0; r < rows.size(); ++r) {
    double x = 10;
    const double y = y0 + 16 + 20 * static_cast<double>(r);
    for (const auto& it : rows[r]) {
      cairo_set_dash(cr, nullptr, 0, 0);
      set(cr, it.c, it.alpha);
      switch (it.kind) {
        case Swatch::Line:
        case Swatch::Dashed:
          if (it.kind == Swatch::Dashed) {
            const double dash[] = {4.0, 3.0};
            cairo_set_dash(cr, dash, 2, 0);
          }
          cairo_set_line_width(cr, 2.5);
          cairo_move_to(cr, x, y - 4);
          cairo_line_to(cr, x + 22, y - 4);
          cairo_stroke(cr);
          break;
        case Swatch::Fill:
          cairo_rectangle(cr, x + 5, y - 10, 12, 12);
          cairo_fill(cr);
          break;
        case Swatch::Wedge:
          cairo_move_to(cr, x + 2, y + 1);
          cairo_arc(cr, x + 2, y + 1, 20, -0.45, -0.05);
          cairo_close_path(cr);
          cairo_fill(cr);
          break;
      }
      cairo_set_dash(cr, nullptr, 0, 0);
      set(cr, colour::kText);
      text(cr, x + 27, y, it.label);
      x += 27 + textWidth(cr, it.label) + 16;
    }
  }
  cairo_restore(cr);
}

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};

cairo_status_t writeToStream(void* closure, const unsigned char* data, unsigned int length) {
  auto* out = static_cast<std::ofstream*>(closure);
  out->write(reinterpret_cast<const char*>(data), length);
  return *out ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

}  // namespace

// ------------------------------------------------------------------------------ public

ImageSize fig8Size(const RenderOptions& o) { return {4 * o.panel_px, kHeaderPx + 2 * o.panel_px + kLegendPx}; }

void checkOptions(const RenderOptions& o) {
  // Below 300 px the legend no longer fits; above 2000 px an image is 8000 px wide.
  if (o.panel_px < 300 || o.panel_px > 2000) throw RenderError("--panel: must be 300 .. 2000 px");
  if (!std::isfinite(o.view_m) || o.view_m < 0.5 || o.view_m > 200) throw RenderError("--view: must be 0.5 .. 200 m");
}

PanelView panelView(int index, const geom::Vec2& centre, const RenderOptions& o) {
  PanelView v;
  v.size = o.panel_px;
  v.x0 = (index % 4) * o.panel_px;
  v.y0 = kHeaderPx + (index / 4) * o.panel_px;
  v.centre = centre;
  v.px_per_m = o.panel_px / o.view_m;
  return v;
}

std::vector<PanelStatus> drawFig8(cairo_t* cr, const Snapshot& s, const sim::Scenario* scenario,
                                  const RenderOptions& o) {
  checkOptions(o);
  const auto size = fig8Size(o);
  cairo_save(cr);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_rectangle(cr, 0, 0, size.width, size.height);
  cairo_fill(cr);
  cairo_restore(cr);

  const bool have_robot = s.robot && finite(*s.robot) && std::abs(s.robot->x) < 1e7 && std::abs(s.robot->y) < 1e7;
  const geom::Vec2 centre = have_robot ? s.robot->position() : geom::Vec2::Zero();

  const std::vector<std::pair<std::string, std::string>> titles = {
      {"a", "Radar Map"},          {"b", "Hypothetical sonar scan"}, {"c", "Real sonar scan"},
      {"d", "Complementary readings"}, {"e", "AGM, operational"},   {"e'", "AGM, tactical"},
      {"f", "Current Sensor Map"}, {"g", "Sector Map"}};
  const std::vector<std::string> chans = {
      channels::RADAR_MAP,       channels::SONAR_HYPOTHESIS, channels::SONAR_RING,
      channels::SONAR_COMPLEMENT, channels::AGM_OPERATIONAL, std::string(channels::AGM_TACTICAL) + " + " + channels::AGM_LINES,
      channels::CURRENT_SENSOR_MAP, channels::SECTOR_MAP};

  std::vector<PanelStatus> out;
  for (int i = 0; i < kPanels; ++i) {
    Panel p;
    p.status.letter = titles[static_cast<size_t>(i)].first;
    p.status.title = titles[static_cast<size_t>(i)].second;
    p.status.channel = chans[static_cast<size_t>(i)];
    p.view = panelView(i, centre, o);
    cairo_save(cr);
    cairo_rectangle(cr, p.view.x0, p.view.y0, p.view.size, p.view.size);
    cairo_clip(cr);
    drawTruth(cr, p.view, s, scenario);
    switch (i) {
      case 0: panelRadarMap(cr, p, s); break;
      case 1: panelHypothesis(cr, p, s); break;
      case 2: panelSonar(cr, p, s); break;
      case 3: panelComplement(cr, p, s); break;
      case 4: panelGrid(cr, p, s, s.agm_operational, channels::AGM_OPERATIONAL, nullptr); break;
      case 5: panelGrid(cr, p, s, s.agm_tactical, channels::AGM_TACTICAL, &s.agm_lines, s.agm_tactical_frame); break;
      case 6: panelCsm(cr, p, s); break;
      case 7: panelSectorMap(cr, p, s); break;
    }
    if (have_robot) drawRobot(cr, p.view, *s.robot, s.robot_radius);
    drawPanelFrame(cr, p);
    cairo_restore(cr);
    out.push_back(p.status);
  }
  drawHeader(cr, s, scenario, o);
  drawLegend(cr, o);
  if (cairo_status(cr) != CAIRO_STATUS_SUCCESS)
    throw RenderError(std::string("drawing failed: ") + cairo_status_to_string(cairo_status(cr)));
  return out;
}

std::vector<PanelStatus> writeFig8Png(const std::string& path, const Snapshot& s,
                                      const sim::Scenario* scenario, const RenderOptions& o) {
  checkOptions(o);
  const auto size = fig8Size(o);
  std::unique_ptr<cairo_surface_t, SurfaceDeleter> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, size.width, size.height));
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw RenderError(std::string("cannot create the image: ") + cairo_status_to_string(cairo_surface_status(surface.get())));
  std::vector<PanelStatus> status;
  {
    std::unique_ptr<cairo_t, ContextDeleter> cr(cairo_create(surface.get()));
    status = drawFig8(cr.get(), s, scenario, o);
  }
  cairo_surface_flush(surface.get());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw RenderError(path + ": cannot open for writing: " + std::strerror(errno));
  const auto st = cairo_surface_write_to_png_stream(surface.get(), writeToStream, &out);
  out.close();
  if (st != CAIRO_STATUS_SUCCESS || !out)
    throw RenderError(path + ": writing the PNG failed: " + cairo_status_to_string(st));
  return status;
}

void releaseStaticData() {
  cairo_debug_reset_static_data();
  FcFini();
}

}  // namespace lasonic::render
