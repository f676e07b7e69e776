#pragma once
// RadarMapMemory (beyond the paper; README "Method", step 3, "What the laser saw behind"): the
// Radar Map lines of earlier scans where the newest scan does not look.
//
// The paper's hypothesis is the ideal sonar on the newest scan's lines, right for MOBOT-IV's
// 360 deg scanner. Behind a 270 deg (or 180 deg) scanner the newest scan has no line, so the
// hypothesis there predicts nothing, and a rear transducer's echo of a wall the robot has just
// passed is "complementary" (or, with complement.outside_laser_view, outside_view) although the
// laser saw that wall seconds earlier: it goes into both grids, placed on the beam's axis, in
// front of the wall (the oblique wall's nearest point lies at the beam's edge), and the sector
// map reports it nearer than the wall. The memory keeps each scan's lines for memory_s and,
// after each new scan, the parts of them that lie where the new scan does not look (the new scan
// decides where it looks, as in the paper). A line whose both ends the scanner saw within
// max_incidence of its normal is not kept: glass sends the laser back only near normal incidence
// (a glint at the foot of the perpendicular, sliding along the pane with the robot), so such a
// line may be a pane's glint, and remembered it would explain the pane's echoes away; a wall
// is kept once some scan saw it obliquely. A reading whose echo arc the newest scan did not
// see, but an earlier one (within memory_s) did, is judged with the hypothesis on the newest
// lines and those of the newest earlier scan that saw its arc: what the laser saw there is what
// the paper's rule compares with. The lines are in the odometry frame; an earlier scan counts
// only where no newer one saw the arc, and over memory_s of driving the odometry's drift stays
// below the classification tolerance (deploy/config/lasonic.yaml). A 360 deg scanner sees
// everywhere: nothing is remembered.
#include <cstdint>
#include <deque>
#include <vector>

#include "complement/radar_map.hpp"
#include "core/geometry.hpp"
#include "core/utime.hpp"

namespace lasonic::complement {

// The parts of `s` that lie where `view` does not look (pieces between the view's two edge rays,
// kept whole where their midpoint is outside), appended to `out` (with s's npoints and rms).
// Nothing for a full-circle view.
void clipOutsideView(const RmSegment& s, const LaserView& view, std::vector<RmSegment>& out);
// True if a scanner at `from` sees both ends of `s` within max_incidence [rad] of its normal.
bool seenOnlyNearNormal(const geom::Segment& s, const geom::Vec2& from, double max_incidence);

class RadarMapMemory {
 public:
  // max_incidence [rad]: lines seen only within this of their normal are not kept (0: all are).
  // min_length [m]: shorter lines are not kept (0: all are).
  explicit RadarMapMemory(double memory_s = 0, double max_incidence = 0, double min_length = 0)
      : memory_us_(secondsToUs(memory_s)), max_incidence_(max_incidence), min_length_(min_length) {}
  bool enabled() const { return memory_us_ > 0; }

  // The newest Radar Map (its utime, view and segments): earlier maps older than memory_s before
  // it are dropped, the others' lines are to be clipped to where its view does not look
  // (clipOutsideView, when seenBefore first returns them); it is kept for the next. A map older
  // than the newest so far is ignored.
  void update(const RadarMap& rm);
  // The lines outside the newest view of the newest earlier map whose view covered the echo arc
  // of a transducer at `sensor` (global pose, beam_width [rad]) at `range` (arcSeen); nullptr
  // if no earlier map within memory_s did.
  const std::vector<RmSegment>* seenBefore(const geom::Pose2& sensor, double range, double beam_width) const;
  // Earlier maps kept, and their lines outside the newest view (for tests and status).
  size_t maps() const { return earlier_.size(); }
  size_t lines() const;  // (clips every map; like seenBefore, not for concurrent callers)
  void clear() { *this = RadarMapMemory(static_cast<double>(memory_us_) * 1e-6, max_incidence_, min_length_); }

 private:
  struct Earlier {
    int64_t utime = 0;
    LaserView view;
    std::vector<RmSegment> segments;          // as that scan saw them
    mutable std::vector<RmSegment> outside;   // their parts outside the newest view ...
    mutable bool clipped = false;             // ... once clipped against it
    const std::vector<RmSegment>& outsideOf(const LaserView& newest) const;
  };
  int64_t memory_us_ = 0;
  double max_incidence_ = 0;
  double min_length_ = 0;
  std::deque<Earlier> earlier_;  // oldest first; the newest map is newest_
  bool have_newest_ = false;
  Earlier newest_;
};

}  // namespace lasonic::complement
