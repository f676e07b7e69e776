#pragma once
// Radar Map (RM): the laser scan's geometric abstraction into line segments (Jörg 1995, sec. 3;
// README "Method", step 1). Every step is a small pure function so each can be tested on its own:
//
//   placeReadings        reading i -> global point, with the robot pose at reading i's own time
//                        (corrects the motion during the scan); no return -> a gap
//   splitClusters        runs of consecutive points, broken at gaps and at range jumps
//   clusterSegments      one cluster -> its line segments (the next three steps)
//   iterativeEndPointFit split a cluster until every point is within split_threshold of its chord
//   fitLine              total-least-squares refit, endpoints projected onto the fitted line
//   joinCorner           neighbouring segments of one cluster end at their lines' intersection
//   extractRadarMap      all of the above; segments with too few points or too short dropped
//
// Gaps stay gaps: a no-return reading always ends a cluster, so a glass door or a black box is
// never bridged by a line (the sonar must be allowed to see what is there).
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {
class PoseHistory;
}

namespace lasonic::complement {

// One laser reading in the sensor frame. `valid` is false for no-return readings (and for
// readings the message layer rejected): they become gaps.
struct LaserReading {
  int64_t utime = 0;   // [us] time this reading was taken (its offset rejected: the scan's utime)
  double angle = 0;    // [rad] sensor frame
  double range = 0;    // [m]
  bool valid = false;
};

struct LaserScan {
  int64_t utime = 0;               // [us] the message's utime, its readings' offsets counted from it
  geom::Pose2 mount;               // sensor pose in the robot frame
  std::vector<LaserReading> readings;  // in scan (angle) order
  bool full_circle = false;        // the last reading neighbours the first (360 deg scanner)
};

// Robot pose (odometry frame) at a time, e.g. PoseHistory::at; nullopt if unknown.
using PoseLookup = std::function<std::optional<geom::Pose2>(int64_t utime)>;

struct RadarMapConfig {
  double jump_abs = 0.10;         // [m] consecutive points farther apart than
  double jump_rel = 0.05;         //     jump_abs + jump_rel * range start a new cluster
  // [m] max point-to-chord distance in a final segment: 5 sigma of the laser's ~1 cm noise. At
  // 0.03 noise alone split walls into slivers that the filters below dropped, leaving false gaps.
  double split_threshold = 0.05;
  int min_points = 6;             // fewer points: dropped (noise, thin objects)
  double min_length = 0.15;       // [m] shorter: dropped
  // Pole candidates (complement/pole_tracker.hpp; 0: none): a cluster that gives no segment (a
  // pipe, a post, a table leg, or a glint of glass: too few points or too short for a line)
  // with at least this many points is kept in RadarMap::pole_candidates.
  int pole_min_points = 1;
};

// A global point of the scan, or a gap (no return / no pose / rejected).
struct ScanPoint {
  geom::Vec2 p = geom::Vec2::Zero();
  double range = 0;
  bool valid = false;
};

struct RmSegment {
  geom::Segment seg;
  int npoints = 0;
  double rms = 0;  // [m] RMS orthogonal distance of its points to the line
};

// Where the scan could see: a scanner of less than a full turn (a 270 deg one) is blind behind,
// and there the Radar Map's lack of a line says nothing.
struct LaserView {
  bool full_circle = true;
  geom::Pose2 sensor;              // the scanner's global pose at the scan's last reading
  double angle_min = 0, angle_max = 0;  // [rad] sensor frame: the first and the last reading's angle
  // True if the scanner could have seen point p (global): a full circle, or p's bearing from the
  // sensor within [angle_min, angle_max].
  bool covers(const geom::Vec2& p) const;
};
// The view of `scan` with the robot at `robot` (the pose at the scan's last reading).
LaserView laserViewOf(const LaserScan& scan, const geom::Pose2& robot);
// The same, knowing also the robot's pose at the scan's earliest reading: a robot that turned
// during the scan took that reading at another heading, so in the last reading's frame it lies
// that much further along. A full-circle scan during which the robot turned against the sweep by
// more than one reading's spacing left a wedge at its seam that no reading looked into (at
// 1 rad/s and 5 scans/s, 11 deg: one and a half sectors): its view is the part the readings
// covered, as a partial scanner's. (A scanner of less than a full turn, or a turn with the sweep:
// the view as above.)
LaserView laserViewOf(const LaserScan& scan, const geom::Pose2& robot, const geom::Pose2& robot_at_first);

// The bearings in which a scan's readings came back empty (an empty reading is no free space:
// the pilot's laser memory keeps earlier returns there). at(p) is true where the reading nearest
// to p's bearing from the view's sensor pose and its two neighbours all had no return (empty[i]
// nonzero for reading i). Readings are taken as evenly spaced from the first to the last
// reading's angle; the last neighbours the first only for a full circle. Holds a reference to
// `view`, which must outlive it.
class DarkBearings {
 public:
  DarkBearings(const LaserScan& scan, const LaserView& view, const std::vector<uint8_t>& empty);
  bool at(const geom::Vec2& p) const;

 private:
  const LaserView& view_;
  std::vector<uint8_t> dark_;  // reading i and both neighbours came back empty
  bool any_ = false;           // some reading is dark: else at() is false everywhere
  bool full_ = false;          // the last reading neighbours the first
  double step_ = 0;
};

// A corner of the Radar Map: two of its segments that meet (end points within `join`) at a
// right angle (within `angle_tol`). A right-angled corner sends sound back parallel to how it
// came (twice reflected), so a neighbouring transducer can hear another's ping by way of it.
struct RmCorner {
  geom::Vec2 vertex;
  geom::Vec2 arm_a, arm_b;  // unit vectors along the two walls, away from the vertex
  // True if p lies inside the corner (in front of both walls' faces that look into it).
  bool inside(const geom::Vec2& p) const;
};
// Defaults: the lines' 5 cm fit threshold; 10 deg off square turns the returned sound by 20 deg,
// still within a neighbour's side lobes.
std::vector<RmCorner> rightAngleCorners(const std::vector<RmSegment>& segments, double join = 0.05,
                                        double angle_tol = geom::deg2rad(10.0));

struct RadarMap {
  int64_t utime = 0;          // [us] time of the scan's last reading
  int64_t source_utime = 0;   // [us] time of the scan's first reading
  geom::Pose2 robot_pose;     // at utime
  std::vector<RmSegment> segments;
  // The clusters that gave no segment (RadarMapConfig::pole_min_points), and the points of those
  // of them that PoleTracker found to be poles: the classification uses them (poleEcho; not in
  // RADAR_MAP).
  std::vector<std::vector<geom::Vec2>> pole_candidates;
  std::vector<geom::Vec2> poles;
  std::vector<RmCorner> corners;  // rightAngleCorners(segments), once per map (not in RADAR_MAP)
  LaserView view;
};

// Indices [first, last] (inclusive) into a point list.
struct IndexRange {
  size_t first = 0, last = 0;
  size_t size() const { return last - first + 1; }
};

// Reading -> global point with the robot pose looked up at the reading's own time. Readings
// whose pose is unknown become gaps; *no_pose (if given) counts them.
std::vector<ScanPoint> placeReadings(const LaserScan& scan, const PoseLookup& pose_at,
                                     int* no_pose = nullptr);
// The same with the poses of an odometry history (PoseHistory::at), found interval by interval.
std::vector<ScanPoint> placeReadings(const LaserScan& scan, const PoseHistory& poses, int* no_pose = nullptr);
// The same into `out`, whose storage is reused (a scan's worth of points, scan after scan).
void placeReadingsInto(const LaserScan& scan, const PoseHistory& poses, std::vector<ScanPoint>& out,
                       int* no_pose = nullptr);

// The widest vector loop placeReadings (from a PoseHistory) and splitClusters may use; all give
// the same values, bit for bit. By default the widest the CPU has (AVX2 where there, else SSE2);
// tests set a narrower one to compare them. Process-wide; a path the CPU lacks is narrowed to
// one it has.
enum class VectorPath { Scalar, Sse2, Avx2 };
void setVectorPath(VectorPath widest);
VectorPath vectorPath();

// Runs of valid consecutive points without a jump. For a full-circle scan a run that crosses
// the end of the list continues at its start; if nothing breaks the circle at all (a closed room
// seen without a gap) the one cluster is `closed`.
struct Cluster {
  std::vector<geom::Vec2> points;
  bool closed = false;
};
std::vector<Cluster> splitClusters(const std::vector<ScanPoint>& points, bool full_circle,
                                   const RadarMapConfig& cfg);

// Line segments of a cluster: iterative end-point fit, then fitLine and the size filters.
// A closed cluster is first cut at one of its corners, so no wall is split at the scan's seam,
// and its last and first segments are joined like every other corner.
std::vector<RmSegment> clusterSegments(const Cluster& cluster, const RadarMapConfig& cfg);

// out[k] = the square of geom::distance(chord, points[k]) for k < count, bit for bit (the
// squared norm of closestPoint(chord, p) - p): the end-point fit's distances.
void chordSquaredDistances(const geom::Segment& chord, const geom::Vec2* points, size_t count, double* out);

// Two consecutive returns farther apart than jump_abs + jump_rel * the nearer range: a new cluster
// (the threshold grows with range because neighbouring rays diverge).
bool rangeJump(const ScanPoint& a, const ScanPoint& b, const RadarMapConfig& cfg);

// Iterative end-point fit of points[r]: split at the point farthest from the chord until every
// point lies within `threshold` of it. The split point belongs to both halves (a corner).
std::vector<IndexRange> iterativeEndPointFit(const std::vector<geom::Vec2>& points, IndexRange r,
                                             double threshold);

// Total-least-squares line through points[r]; the segment runs from the projection of the first
// point to that of the last.
RmSegment fitLine(const std::vector<geom::Vec2>& points, IndexRange r);

// a and b are neighbours in one cluster (split at a corner, perhaps with a dropped sliver between
// them): end both at the
// intersection of their lines, unless the lines are nearly parallel or the intersection lies
// more than max_shift from either endpoint. Without this a wall would end up to one ray spacing
// short of the corner (at the projection of the reading nearest to it).
void joinCorner(RmSegment& a, RmSegment& b, double max_shift);

// The time of the scan's latest reading (its utime if it has none): a Radar Map's time and pose.
int64_t lastReadingTime(const LaserScan& scan);
// The time of its earliest reading (its utime if it has none): a Radar Map's source_utime.
int64_t firstReadingTime(const LaserScan& scan);

// The segments of the placed readings (clusters, end-point fit, size filters) appended to
// `segments`, and, if given, the clusters that gave none to `pole_candidates`
// (RadarMapConfig::pole_min_points): the Radar Map's segments without the rest of the map.
void appendScanSegments(const std::vector<ScanPoint>& points, bool full_circle, const RadarMapConfig& cfg,
                        std::vector<RmSegment>& segments, std::vector<std::vector<geom::Vec2>>* pole_candidates = nullptr);

RadarMap extractRadarMap(const LaserScan& scan, const PoseLookup& pose_at, const RadarMapConfig& cfg,
                         int* no_pose = nullptr);
RadarMap extractRadarMap(const LaserScan& scan, const PoseHistory& poses, const RadarMapConfig& cfg,
                         int* no_pose = nullptr);
// The same from readings already placed with `poses` (placeReadings(scan, poses), e.g. through a
// SharedPlacement): extractRadarMap(scan, poses, cfg) is radarMapFromPlaced(scan,
// placeReadings(scan, poses), poses, cfg).
RadarMap radarMapFromPlaced(const LaserScan& scan, const std::vector<ScanPoint>& placed, const PoseHistory& poses,
                            const RadarMapConfig& cfg);

}  // namespace lasonic::complement
