#pragma once
// Sector Map (SCM; Jörg 1995, section 3.4; README "Method", step 5): the pilot's polar world model.
//
// n sectors (paper: 48 of 7.5 deg) in the robot frame; sector k covers bearings
// [-pi + k*2pi/n, -pi + (k+1)*2pi/n) (0 = straight ahead, counter-clockwise). Each holds the
// free distance from the robot's boundary (a circle of robot_radius) to the nearest obstacle in
// it, if that is at most max_range:
// - laser value: the newest scan's points, kept in the global frame (each placed with the pose
//   at its own time), moved into the current robot pose;
// - sonar value: operational-AGM cells with Gp >= gp_threshold, in the sector of the cell
//   centre's bearing, at (sonar_cell_point) the point of the square nearest to the robot centre
//   (never farther than any part of the cell; but up to c*sqrt(2) nearer than the echo that made
//   it) or at the cell centre (within c/sqrt(2) of the echo either way). Beyond the paper:
//   cells whose centre lies within laser_explains_radius of a point of the newest (not stale)
//   scan do not count: the laser already reports that obstacle, at its 0.5 deg bearing, so the
//   sonar part keeps only what the laser does not see -- the complement idea applied to the
//   scan's points, which hold thin things (a 2 cm pipe) that the Radar Map's lines leave out;
// - copy rule: a sector's own sonar value is copied into both adjacent sectors (the trivial
//   sensor model's bearing error is half the beam width), except into a sector that holds sonar
//   data of its own; a copy takes the min with other copies and never makes a sector freer.
//   copy_over_own (beyond the paper): into those too, where it is nearer than the sector's own
//   value -- the bearing error is there whether or not the sector has a (farther) cell of its
//   own: a surface seen obliquely is nearest at the edge its neighbour's cell lies beyond;
//   CopyRule::UnlessLaserConfirmed (beyond the paper): nor is a value copied out of a sector
//   whose laser value lies within copy_confirm_tolerance of it: the laser (0.5 deg rays) has
//   then put that obstacle in this sector, so the bearing error the copy guards against is
//   not there (a thin pipe that the Radar Map's lines leave out but the scan's points hold);
// - remembered value (beyond the paper; off unless the caller gives remembered points): the
//   navigator's stable tactical map (its occupied cells, at their centres), the static obstacles
//   the sonar located seconds ago; cells the newest scan explains do not count. It is used only
//   while fresh (remembered_stale_s) and only ever adds an obstacle: stale, absent or far, the map
//   is exactly what it would be without it;
// - the sector value is the smallest of laser, sonar and remembered (ties: laser, then sonar),
//   with its source recorded.
// Staleness: a sensor whose newest data is more than its limit older than the map's time is
// stale. Its values are then its last data moved with odometry (StaleValues::Moved: the laser's
// last scan points and the AGM's cells are in the odometry frame, so a static obstacle stays
// where it was seen), or held (StaleValues::HeldMin): each sector takes the min of the newly
// computed value and the held one, and the held values only ever get shorter, so stale data
// never makes a sector look freer than the last fresh data did, also where the robot has
// moved or turned away since; or (StaleValues::Frontier) moved as with Moved, the laser's last
// scan together with its shadow edges (setLaserScan, operational/laser_shadow.hpp), so that a
// sector reports the nearest place the last scan did not see free. A sensor never heard from is
// stale with age -1.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "core/geometry.hpp"
#include "operational/agm.hpp"

namespace lasonic {

// Values equal sector_map_t::SOURCE_*.
enum class SectorSource : int8_t { None = 0, Laser = 1, Sonar = 2, SonarCopied = 3, Remembered = 4 };

// Where an AGM cell's obstacle is taken to be (see the file comment).
enum class CellPoint { Nearest, Centre };
// Which own sonar values are copied into the neighbours (see the file comment).
enum class CopyRule { Paper, UnlessLaserConfirmed, CellExtent };
// What a stale sensor's sector values are (see the file comment).
enum class StaleValues { Moved, HeldMin, Frontier };

struct SectorMapParams {
  int sectors = 48;             // paper: 48 sectors of 7.5 deg
  double robot_radius = 0.35;   // [m] the robot's boundary circle
  double max_range = 3.0;       // [m] from the boundary; farther obstacles are not reported
  int gp_threshold = 2;         // AGM cells with Gp >= this count as obstacles
  CellPoint sonar_cell_point = CellPoint::Nearest;
  double laser_explains_radius = 0;      // [m] 0: every cell counts (the paper)
  CopyRule copy_rule = CopyRule::Paper;
  double copy_confirm_tolerance = 0.10;  // [m] |laser - sonar| within this: laser-confirmed
  bool copy_over_own = false;            // copies also into sectors with sonar data of their own
  // false (beyond the paper): a cell the AGM keeps beyond h_max because no sound went through it
  // (AccumulativeGridMap::held) gives its sector a value but no copies.
  bool copy_held = true;
  double laser_stale_s = 0.5;   // [s] laser data older than this is stale
  double sonar_stale_s = 0.5;   // [s] sonar (complement) data older than this is stale
  StaleValues stale_values = StaleValues::HeldMin;
  double remembered_stale_s = 2.0;  // [s] a remembered (tactical) map older than this is not used
  // [m] a remembered cell within this of a point of the newest (not stale) scan is the obstacle
  // the laser reports already (0: laser_explains_radius, as for the AGM's cells).
  double remembered_explains_radius = 0;
};

// Any grid of obstacle cells laid out like the AGM -- global cell (gx, gy) covers
// [gx*c, (gx+1)*c) x [gy*c, (gy+1)*c), the window holds gx in [origin_x, origin_x + size), gy
// likewise -- so that other mappers (the evaluation's baselines) are read out by the same
// SectorMap as the operational AGM. An occupied cell counts as above any gp_threshold.
struct OccupancyWindow {
  int64_t origin_x = 0, origin_y = 0;
  int size = 0;
  double cell_size = 0.10;
  std::vector<uint8_t> occupied;  // row-major, iy * size + ix; nonzero: an obstacle

  // The AccumulativeGridMap interface that SectorMap reads.
  int64_t originX() const { return origin_x; }
  int64_t originY() const { return origin_y; }
  double cellSize() const { return cell_size; }
  geom::Vec2 originMetres() const {
    return {static_cast<double>(origin_x) * cell_size, static_cast<double>(origin_y) * cell_size};
  }
  template <typename F>
  void forEachCell(int ix0, int iy0, int ix1, int iy1, F&& f) const {
    ix0 = std::max(ix0, 0);
    iy0 = std::max(iy0, 0);
    ix1 = std::min(ix1, size - 1);
    iy1 = std::min(iy1, size - 1);
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix) {
        const bool occ = occupied[static_cast<size_t>(iy) * static_cast<size_t>(size) + static_cast<size_t>(ix)] != 0;
        f(ix, iy, occ ? 1 : 0, occ ? std::numeric_limits<int>::max() : 0);
      }
  }
  template <typename F>
  void forEachWeightedCell(int ix0, int iy0, int ix1, int iy1, F&& f) const {
    forEachCell(ix0, iy0, ix1, iy1, [&f](int ix, int iy, int g, int gp) {
      if (g > 0) f(ix, iy, g, gp);
    });
  }
  bool held(int, int) const { return false; }
};

// out[i] = clamp(floor(v[i] / cell), -1e15, 1e15) for i < n: cell indices, as SectorMap takes
// them for the explained cells (several at once).
void cellIndices(const double* v, size_t n, double cell, int64_t* out);

struct SectorMapState {
  int64_t utime = 0;
  geom::Pose2 pose;
  // Per sector, [m]; -1 = nothing known (within max_range).
  std::vector<float> distance, laser, sonar, remembered;
  std::vector<SectorSource> source;
  bool laser_stale = true, sonar_stale = true, remembered_stale = true;
  double laser_age_s = -1, sonar_age_s = -1, remembered_age_s = -1;  // -1: never received
};

class SectorMap {
 public:
  explicit SectorMap(const SectorMapParams& p);
  const SectorMapParams& params() const { return p_; }
  // The laser's staleness limit [s] from now on (the pilot's, in the laser's own scan periods);
  // a value that is not positive and finite changes nothing.
  void setLaserStaleS(double s) {
    if (std::isfinite(s) && s > 0) p_.laser_stale_s = s;
  }

  // Sector of a robot-frame bearing.
  int sectorOf(double bearing) const;

  // The newest laser scan: its returns in the global frame; utime: time of its newest reading.
  // Returns the previous scan's list emptied, its storage kept for the caller's next scan.
  std::vector<geom::Vec2> setLaserPoints(int64_t utime, std::vector<geom::Vec2> points);
  // The newest scan's returns as set (with whatever the caller added: remembered returns).
  const std::vector<geom::Vec2>& laserPoints() const { return laser_points_; }
  // Returns of the same scan found moving (operational/mover_prediction.hpp), left out of
  // setLaserPoints' list: each is reported at p + v * min(age, horizon_s), age = the map's time
  // minus the return's. They explain no AGM cell. Cleared by setLaserPoints.
  struct MovingPoint {
    geom::Vec2 p = geom::Vec2::Zero();
    geom::Vec2 v = geom::Vec2::Zero();  // [m/s]
    int64_t utime = 0;
  };
  void setLaserMovers(std::vector<MovingPoint> movers, double horizon_s);
  // The newest scan's readings in scan order (returns, global frame; valid 0: a reading that came
  // back empty) and the scanner's position then: under StaleValues::Frontier, once the laser is
  // stale, its shadow edges (operational/laser_shadow.hpp, as far as twice the map's reach) are
  // made from them and reported with its returns. Cleared by setLaserPoints. (Storage swapped:
  // the arguments get the previous scan's.)
  void setLaserScan(std::vector<geom::Vec2>& returns, std::vector<uint8_t>& valid, const geom::Vec2& origin,
                    bool full_circle);
  // Time of the newest sonar data the AGM holds (the newest complement message).
  void setSonarTime(int64_t utime);
  // The newest remembered obstacles (the tactical map's occupied cells, global frame) and the
  // time of that map.
  void setRemembered(int64_t utime, std::vector<geom::Vec2> points);

  // Computes the map at utime with the robot at `pose` (odometry frame).
  const SectorMapState& update(int64_t utime, const geom::Pose2& pose, const AccumulativeGridMap& agm);
  // The same with another mapper's obstacle cells in place of the AGM's.
  const SectorMapState& update(int64_t utime, const geom::Pose2& pose, const OccupancyWindow& grid);
  const SectorMapState& state() const { return s_; }

  // The widest vector loop the laser part may use; all give the same values. By default the
  // widest the CPU has (AVX2 where there, else SSE2); tests set a narrower one to compare them.
  // Process-wide; set it before maps are updated. A path the CPU lacks is narrowed to one it has.
  enum class VectorPath { Scalar, Sse2, Avx2 };
  static void setVectorPath(VectorPath widest);
  static VectorPath vectorPath();

 private:
  struct Value {
    float d = -1;  // -1: none
    SectorSource src = SectorSource::None;
  };
  int sectorOfNormalized(double bearing) const;  // bearing in [-pi, pi]
  // The sector of direction (x, y), found without atan2 when the direction lies clearly inside
  // a sector (see the definition); otherwise exact(), the defining computation.
  template <typename Exact>
  int sectorOfDirection(double x, double y, Exact&& exact) const;
  // Direction (x, y) lies inside sector k by a relative margin of 1e-9 (then k is its sector).
  bool clearlyInside(int k, double x, double y) const;
  // (ct, st: cos and sin of pose.theta; shadow: the shadow edges too.)
  void laserValues(const geom::Pose2& pose, double ct, double st, bool shadow, std::vector<Value>& out) const;
  void rememberedValues(const geom::Pose2& pose, double ct, double st, std::vector<Value>& out, bool check_laser) const;
  bool explained(const geom::Vec2& p) const;
  // A point of the newest scan within rho of p (buckets of size rho, rebuilt once per scan).
  bool laserNear(const geom::Vec2& p, double rho) const;
  void rebuildLaserBuckets(double rho);
  bool explainedCell(int64_t gx, int64_t gy) const;
  int64_t explainedGlobal(double v) const;  // global cell index at the explained cells' size
  bool explainedBy(int64_t x, int64_t y, const geom::Vec2& p) const;  // p explains cell (x, y)
  bool withinRho(int64_t x, int64_t y, const geom::Vec2& p) const;    // centre of (x, y) within rho of p
  template <typename Grid>
  void sonarValues(const geom::Pose2& pose, double ct, double st, const Grid& agm, bool use_explained,
                   std::vector<Value>& out, std::vector<Value>& spread, std::vector<Value>& copyable) const;
  template <typename Grid>
  const SectorMapState& updateWith(int64_t utime, const geom::Pose2& pose, const Grid& agm);
  void rebuildExplained(double cell_size);
  // Staleness (HeldMin): fresh -> remember; stale -> min with what is held (which only shrinks).
  void hold(bool stale, std::vector<Value>& now, std::vector<Value>& held) const;

  SectorMapParams p_;
  double reach_root_bound_ = 0;  // the largest r^2 whose root is <= robot_radius + max_range
  std::vector<double> bound_c_, bound_s_;  // unit vector of each sector's lower edge, k = 0..n
  std::vector<geom::Vec2> laser_points_;
  std::vector<double> laser_x_, laser_y_;  // the same points, x and y apart (laserValues, four at a time)
  // The global cells (gx, gy) the newest scan explains (see rebuildExplained), over their
  // bounding box [explained_x0_, +explained_w_) x [explained_y0_, +explained_h_): decided when
  // first asked (explained_known_, one bit per cell; the answer in explained_bits_) from the
  // scan's points bucketed by cell (run by run); or, for a box too large for that, a sorted list.
  mutable std::vector<uint64_t> explained_known_, explained_bits_;
  int64_t explained_x0_ = 0, explained_y0_ = 0, explained_w_ = 0, explained_h_ = 0;
  int64_t explained_span_ = 0;  // candidate box half-width [cells]
  double explained_rho2_ = 0;   // the largest squared distance whose root is <= laser_explains_radius
  std::vector<uint32_t> bucket_start_;  // per bucket (row-major, bucket_w_ wide) its first run; + end
  // The runs of the scan's points in one bucket, bucket after bucket: [first, end) of laser_points_.
  std::vector<std::pair<uint32_t, uint32_t>> bucket_runs_;
  std::vector<uint32_t> bucket_fill_, point_bucket_, run_first_;  // (scratch of rebuildExplained)
  std::vector<int64_t> point_gx_, point_gy_;  // (scratch: each point's cell)
  int64_t bucket_w_ = 0, bucket_shift_ = 0;  // buckets per row; log2 of a bucket's side [cells]
  std::vector<std::pair<int64_t, int64_t>> explained_;  // sorted; only when the box is too large
  bool explained_any_ = false;
  double explained_cell_size_ = 0;                       // 0: to be rebuilt
  std::vector<std::pair<std::pair<int64_t, int64_t>, geom::Vec2>> laser_buckets_;  // sorted by bucket
  double laser_bucket_size_ = 0;                                                   // 0: to be rebuilt
  std::vector<MovingPoint> laser_movers_;
  std::vector<geom::Vec2> scan_returns_;  // setLaserScan's
  std::vector<uint8_t> scan_valid_;
  geom::Vec2 scan_origin_ = geom::Vec2::Zero();
  bool scan_full_circle_ = false, shadow_made_ = false;
  std::vector<geom::Vec2> laser_shadow_;  // made from them when first needed
  double movers_horizon_s_ = 0;
  std::vector<geom::Vec2> remembered_points_;
  int64_t laser_utime_ = 0, sonar_utime_ = 0, remembered_utime_ = 0;
  bool have_laser_ = false, have_sonar_ = false, have_remembered_ = false;
  mutable std::vector<double> laser_r2_;  // laserValues' scratch: per sector the smallest r^2
  std::vector<Value> laser_now_, sonar_own_, sonar_reach_, sonar_now_, held_laser_, held_sonar_, remembered_now_;
  std::vector<Value> sonar_copyable_;  // copy_held false: the own values of cells not held
  SectorMapState s_;
};

}  // namespace lasonic
