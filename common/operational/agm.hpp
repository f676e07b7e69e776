#pragma once
// Accumulative Grid Map (AGM; Jörg 1995, sections 3.2-3.3; README "Method", step 4).
//
// A window of N x N square cells on an imaginary global grid anchored at the global (odometry)
// origin: global cell (gx, gy) covers [gx*c, (gx+1)*c) x [gy*c, (gy+1)*c). The window holds the
// cells gx in [ox, ox+N), gy in [oy, oy+N); window cell (ix, iy) is global cell (ox+ix, oy+iy).
// It follows the robot's translations in whole cells, never its rotations, so a cell keeps its
// global coordinates for as long as it stays in the window.
//
// Storage is a circular buffer: global cell (gx, gy) always lives in slot (gx mod N, gy mod N),
// so re-centring touches only the cells that leave the window (they are forgotten).
//
// Per cell: weight G (belief in occupancy) and frequency H (update cycles since G was last
// incremented). One update cycle = one call of update(): accumulation (trivial sensor model:
// each hit increments G of the one cell containing it, H := 0; G saturates at g_max), revision
// (a cell with G > 0 whose H exceeds h_max gets G := 0; with hold_unpassed, beyond the paper,
// not while no sound went through it since, up to hold_unpassed cycles more) and propagation
//   Gu(i,j) = sum_{p,q=-t..t} G(i+p, j+q),   Gp(i,j) = Gu if G(i,j) > 0 and Gu >= G_T, else 0.
// Cells outside the window count as G = 0.
//
// Cost: H is kept as the cycle of the last increment (H = cycle - last_hit) and revisions come
// from a queue of hits in time order, and Gu/Gp are updated over the (2t+1)^2 neighbourhood of
// every cell whose G changes. A cycle therefore costs O((hits + revisions) * (2t+1)^2),
// independent of N and of the number of occupied cells; after every cycle G, H, Gu and Gp equal
// what the batch definitions above give.
#include <algorithm>
#include <cstdint>
#include <deque>
#include <limits>
#include <vector>

#include "core/config.hpp"
#include "core/geometry.hpp"
#include "core/int_scan.hpp"
#include "core/odometry_error.hpp"

namespace lasonic {

struct AgmParams {
  int size = 100;                     // N (paper: 100 x 100)
  double cell_size = 0.10;            // [m]
  int g_max = 100;                    // G saturates here (fits the int16 of grid_map_t)
  int h_max = 12;                     // revision once H > h_max [update cycles]
  int t = 1;                          // propagation neighbourhood (2t+1) x (2t+1)
  int g_threshold = 2;                // G_T
  // The largest Gp can be: G summed over the (2t+1)^2 cluster, each at most g_max (a Gp
  // threshold above it is never reached).
  double maxGp() const { return (2.0 * t + 1) * (2.0 * t + 1) * g_max; }
  // [m] How far around the robot the window reaches wherever re-centring lets the robot be:
  // (size/2 - recenter_max_cells - 1) * cell_size.
  double guaranteedView() const { return (size / 2 - recenter_max_cells - 1) * cell_size; }
  int recenter_max_cells = 5;         // k at standstill
  int recenter_min_cells = 1;         // k is never below this
  double recenter_lookahead_s = 1.0;  // k shrinks by the whole cells driven in this time
  // Also keep, per cell, the mean of the points its hits landed on (beyond the paper: the grid's
  // weights are unchanged; consumers that fit geometry, like line generation, then use where the
  // echoes were instead of the cell centre, free of the cell's quantisation error).
  bool hit_centroids = false;
  // Also forget a cell once the robot has driven this far [m] since its last increment (0: off;
  // beyond the paper, for long memories: what limits them is the odometry's drift per metre
  // driven, not time). Distance = the sum of the moves between the positions given to follow().
  double h_max_m = 0;
  // Also forget a cell once the odometry's expected (1 sigma) displacement between where the cell
  // was heard and the robot now exceeds this [m] (0: off; beyond the paper). Odometry modelled as
  // random walks: distance error trans_noise [m/sqrt(m)], heading error drift_noise [rad/sqrt(m)]
  // from driving and rot_noise [rad/sqrt(rad)] from turning; a heading error made at one moment
  // displaces what was heard before it by the distance driven after it. So a turn on the spot
  // costs nothing at once, but the way back after it costs more than the way out: the memory of
  // a there-and-back path lasts as long as the odometry keeps it within this error.
  double forget_sigma_m = 0;
  double odometry_trans_noise = 0.01;
  double odometry_rot_noise = 0.005;
  double odometry_drift_noise = 0.002;
  // Arc votes (beyond the paper; 0: off): besides G, every cell keeps how many echo arcs (range
  // arcs within the echo's bearing uncertainty, EchoPlacer's arc placement) passed through it
  // lately, each vote fading with this time constant [update cycles]. Arcs of one surface heard
  // from several poses cross where the surface is: that is where their echoes' cells go.
  double arc_vote_tau = 0;
  // Forgetting only what the sonar could have heard (beyond the paper; 0: off): a cell whose H
  // passes h_max is kept, up to this many update cycles longer, while no sound went through it
  // since its last hit (markPassed; operational/sound_passed.hpp). The paper forgets a cell not
  // hit again within h_max because a reflector still there would have answered; but a beam
  // answers from its nearest reflector only, so a surface it still hears at that range answers
  // on other cells, and a beam that missed the cell (between beams, behind a nearer echo) says
  // nothing of it either.
  int hold_unpassed = 0;
};
// A G_T that a person walking past does not reach: walking at `walking_speed` [m/s] they cross
// a neighbourhood `neighbourhood_m` wide ((2t+1) cells) in neighbourhood_m / walking_speed; each
// of the `transducers` whose beams overlap there (at most: maxBeamOverlap in
// operational/sonar_bearing.hpp; MOBOT-IV's and a Pioneer's rings 2, a ring of 8 whose beams do
// not overlap 1) hears them at most once per ring cycle of `ring_cycle_s`, so they give at most
// transducers neighbourhood_m / (walking_speed ring_cycle_s) echoes, and G_T is one more (at most
// 1e6). -1 if an argument is not positive and finite.
int walkerGThreshold(double neighbourhood_m, double walking_speed, double ring_cycle_s, int transducers);

// Reads the keys of an AGM config section over `base` (defaults of the level using it).
// Throws ConfigError naming the key path.
AgmParams agmParams(const Config& c, AgmParams base = {});

class AccumulativeGridMap {
 public:
  explicit AccumulativeGridMap(const AgmParams& p);

  const AgmParams& params() const { return p_; }
  int size() const { return n_; }
  double cellSize() const { return p_.cell_size; }
  // Global cell index of window cell (0, 0).
  int64_t originX() const { return ox_; }
  int64_t originY() const { return oy_; }
  // Global position of the window's lower-left corner.
  geom::Vec2 originMetres() const;
  // Update cycles run so far.
  int64_t cycle() const { return cycle_; }

  // Re-centring rule: the robot may be up to k(v) cells (Chebyshev distance) from the centre
  // cell, k(v) = clamp(recenter_max_cells - floor(|v| * recenter_lookahead_s / cell_size),
  // recenter_min_cells, recenter_max_cells): the faster the robot, the sooner the window moves,
  // so the view ahead stays at least N/2 - k(v) cells.
  int recenterLimit(double speed) const;
  // Moves the window (whole cells) so that the robot's cell becomes the centre cell
  // (ix = iy = N/2) when the robot is farther than recenterLimit(speed) from it.
  // Returns true if the window moved. Also advances the odometer (h_max_m).
  // heading (optional, radians): the turn since the previous call, for forget_sigma_m.
  bool follow(const geom::Vec2& robot, double speed, double heading = std::numeric_limits<double>::quiet_NaN());
  double odometer() const { return odometer_; }
  // The error model of the moves given to follow() from now on (forget_sigma_m).
  void setOdometryNoise(const OdometryNoise& n) { odometry_error_.setNoise(n); }
  // Centres the window on p unconditionally.
  void centreOn(const geom::Vec2& p);

  // One update cycle with the global hit points of its readings. Returns how many hits fell
  // inside the window (the others are ignored).
  int update(const std::vector<geom::Vec2>& hits);
  // The revision's h_max [update cycles] from the next update on (the pilot sets it to three ring
  // cycles once it has counted the ring's firing groups).
  void setHMax(int h_max) { p_.h_max = std::max(0, h_max); }
  // hold_unpassed [update cycles] from the next update on (the pilot sets it in ring cycles).
  void setHoldUnpassed(int cycles) { p_.hold_unpassed = std::max(0, cycles); }
  // Sound went through window cell (ix, iy) in the coming update cycle with nothing answering
  // there (call before update(); a hit in the same cycle outweighs it). Only hold_unpassed uses it.
  void markPassed(int ix, int iy);
  // Cells kept beyond h_max now because no sound went through them (hold_unpassed).
  size_t held() const { return held_.size(); }
  // Window cell (ix, iy) is one of them.
  bool held(int ix, int iy) const {
    const size_t s = slot(ix, iy);
    return p_.hold_unpassed > 0 && g_[s] > 0 && cycle_ - last_hit_[s] > p_.h_max;
  }
  // G_T from now on (at least 1): every cell's Gp follows at once (Gu is kept for every cell, so
  // this is one pass over the window; the navigator sets it once it has timed the ring).
  void setGThreshold(int g_threshold);
  // Empties every cell whose centre lies within r of c (G := 0, its hits forgotten, its
  // neighbours' propagated weight lowered). Returns how many were emptied.
  int clearDisc(const geom::Vec2& c, double r);

  // Window cell of a global point; false if outside the window.
  bool cellAt(const geom::Vec2& p, int& ix, int& iy) const;

  // cellAt(centre + range * geom::unitVector(b)) for the bearings b of an arc, taken one after
  // the other `step` apart (b = b0 + q * step as the caller rounds it): the same cells, mostly
  // without a sin and cos and a division per sample. The previous sample's unit vector is turned
  // by the step, and the cell of its point taken where that point lies farther from the cell's
  // edges than the turns' rounding could have moved it (a bound about a thousand times the
  // error); otherwise, and for the first sample, the defining computation.
  class ArcCells {
   public:
    ArcCells(const AccumulativeGridMap& agm, const geom::Vec2& centre, double range, double step);
    bool cellAt(double b, int& ix, int& iy);

   private:
    const AccumulativeGridMap& agm_;
    geom::Vec2 centre_;
    double range_, step_, c_ = 1, s_ = 0, inv_cell_;
    bool turn_;            // the turn may be used (finite, moderate values)
    bool seeded_ = false;  // u_ is the unit vector of seed_ turned k_ times
    double ux_ = 0, uy_ = 0, seed_ = 0;
    int64_t k_ = 0;
  };
  // Global position of window cell (ix, iy)'s lower-left corner.
  geom::Vec2 cellCorner(int ix, int iy) const;

  // Window-coordinate accessors (0 <= ix, iy < N).
  int g(int ix, int iy) const { return g_[slot(ix, iy)]; }
  int h(int ix, int iy) const;  // 0 where G == 0
  int gu(int ix, int iy) const { return gu_[slot(ix, iy)]; }
  int gp(int ix, int iy) const { return gp_[slot(ix, iy)]; }
  // Update cycle (1, 2, ...) of the cell's last increment; 0 where G == 0.
  int64_t lastHitCycle(int ix, int iy) const;
  // Global position of the mean of the hits that built the cell's weight (hit_centroids), else
  // (or for a cell without weight) its centre.
  geom::Vec2 evidencePoint(int ix, int iy) const;

  // Arc votes (arc_vote_tau > 0): adds `weight` votes (one, unless the arc is worth less: a look
  // from where the robot already was; not positive: none) to every window cell the arc of radius
  // `range` around `centre` crosses between the bearings lo and hi (global frame), and reads a
  // cell's votes, faded to the current cycle. Without arc votes both do nothing / return 0.
  void addArcVotes(const geom::Vec2& centre, double range, double lo, double hi, double weight = 1.0);
  double arcVotes(int ix, int iy) const;

  // Calls f(ix, iy, G, Gp) for every window cell of [ix0, ix1] x [iy0, iy1] (clipped to the
  // window), without a division per cell.
  template <typename F>
  void forEachCell(int ix0, int iy0, int ix1, int iy1, F&& f) const;
  // forEachCell's calls for the cells with G > 0 only, in the same (row-major) order; the empty
  // cells, most of a map, are passed over four at a time.
  template <typename F>
  void forEachPositiveCell(int ix0, int iy0, int ix1, int iy1, F&& f) const;
  // Calls f(ix, iy, G, Gp) once for every window cell of [ix0, ix1] x [iy0, iy1] with G > 0 (the
  // only cells whose Gp can be above 0), in no particular order. Every such cell has its last
  // increment in the revision queue (or among the held cells), so when those are fewer than the
  // rectangle's cells they are walked instead: the operational AGM's few dozen weighted cells,
  // not the thousands of the rectangle.
  template <typename F>
  void forEachWeightedCell(int ix0, int iy0, int ix1, int iy1, F&& f) const;

  // Row-major copies (index iy*N + ix) for grid_map_t.
  void exportGrids(std::vector<int16_t>& g, std::vector<int16_t>& h, std::vector<int32_t>& gp) const;
  // The same for the w x w sub-window whose cell (0, 0) is window cell (ix0, iy0) (index
  // iy*w + ix); the sub-window must lie inside the window.
  void exportGrids(int ix0, int iy0, int w, std::vector<int16_t>& g, std::vector<int16_t>& h,
                   std::vector<int32_t>& gp) const;

 private:
  static int64_t floorMod(int64_t a, int64_t n) { return ((a % n) + n) % n; }
  size_t slotGlobal(int64_t gx, int64_t gy) const {
    return static_cast<size_t>(floorMod(gx, n_) + floorMod(gy, n_) * n_);
  }
  size_t slot(int ix, int iy) const { return slotGlobal(ox_ + ix, oy_ + iy); }
  bool inWindow(int64_t gx, int64_t gy) const {
    return gx >= ox_ && gx < ox_ + n_ && gy >= oy_ && gy < oy_ + n_;
  }
  int64_t globalCell(double v) const;
  // Clips the rectangle [ix0, ix1] x [iy0, iy1] to the window; false if nothing is left.
  bool clipToWindow(int& ix0, int& iy0, int& ix1, int& iy1) const {
    ix0 = std::max(ix0, 0);
    iy0 = std::max(iy0, 0);
    ix1 = std::min(ix1, n_ - 1);
    iy1 = std::min(iy1, n_ - 1);
    return ix0 <= ix1 && iy0 <= iy1;
  }
  // G(gx, gy) += delta; Gu and Gp of its neighbourhood (inside the window) follow.
  void addWeight(int64_t gx, int64_t gy, int delta);
  void moveTo(int64_t nox, int64_t noy);
  void clearAll();

  AgmParams p_;
  int n_;
  int64_t ox_ = 0, oy_ = 0;
  int64_t cycle_ = 0;
  std::vector<int32_t> g_, gu_, gp_;
  std::vector<int64_t> last_hit_;  // cycle of the last increment of G (H = cycle_ - last_hit_)
  // hit_centroids: sums of the hits' offsets from their cell's lower-left corner, and their count
  // (reset whenever G falls to 0).
  std::vector<float> hx_, hy_;
  std::vector<int32_t> hn_;
  // arc_vote_tau: votes at cycle av_cycle_ (read faded by exp(-(cycle_ - av_cycle_) / tau)).
  std::vector<float> av_;
  std::vector<int64_t> av_cycle_;
  // exp(-age / tau) for ages 0 .. kFadeAges-1 cycles, taken once (the same expression, so the
  // same values): fadedVotes is read for every sample of every arc.
  static constexpr int64_t kFadeAges = 1024;
  std::vector<double> fade_;
  void forgetHits(size_t s) {
    if (p_.hit_centroids) hx_[s] = hy_[s] = 0, hn_[s] = 0;
  }
  double fadedVotes(size_t s) const;
  struct Hit {
    int64_t gx, gy, cycle;
    double odometer;
    OdometryError::Mark odometry;  // forget_sigma_m
  };
  OdometryError odometry_error_;
  double odometer_ = 0;  // [m] driven so far (follow() positions)
  bool have_robot_ = false;
  geom::Vec2 last_robot_ = geom::Vec2::Zero();
  double last_heading_ = std::numeric_limits<double>::quiet_NaN();
  std::deque<Hit> hits_;  // increments in cycle order: the revision candidates
  // hold_unpassed: the cycle sound last went through each cell (0: never), and the cells kept
  // beyond h_max (their last increment's entry, moved here from hits_ when it expired).
  std::vector<int64_t> passed_;
  std::vector<Hit> held_;
  std::vector<uint8_t> is_held_;  // by slot: an entry of held_ stands for the cell
  void reviseHeld();
};

template <typename F>
void AccumulativeGridMap::forEachCell(int ix0, int iy0, int ix1, int iy1, F&& f) const {
  if (!clipToWindow(ix0, iy0, ix1, iy1)) return;
  const int sx0 = static_cast<int>(floorMod(ox_ + ix0, n_));
  int sy = static_cast<int>(floorMod(oy_ + iy0, n_));
  for (int iy = iy0; iy <= iy1; ++iy) {
    const size_t row = static_cast<size_t>(sy) * static_cast<size_t>(n_);
    int sx = sx0;
    for (int ix = ix0; ix <= ix1; ++ix) {
      f(ix, iy, g_[row + static_cast<size_t>(sx)], gp_[row + static_cast<size_t>(sx)]);
      if (++sx == n_) sx = 0;
    }
    if (++sy == n_) sy = 0;
  }
}

template <typename F>
void AccumulativeGridMap::forEachPositiveCell(int ix0, int iy0, int ix1, int iy1, F&& f) const {
  if (!clipToWindow(ix0, iy0, ix1, iy1)) return;
  const int sx0 = static_cast<int>(floorMod(ox_ + ix0, n_));
  const int w = ix1 - ix0 + 1;
  const int before_wrap = std::min(w, n_ - sx0);  // a row is at most two runs of consecutive slots
  const int32_t* const g = g_.data();
  const int32_t* const gp = gp_.data();
  // Cells ix0 + k0 + j for j in [0, len), in slots first_slot + j.
  const auto run = [&](int iy, const size_t first_slot, int k0, int len) {
    const int32_t* const gr = g + first_slot;
    const int32_t* const gpr = gp + first_slot;
    const int x0 = ix0 + k0;
    forEachAtLeast(gr, static_cast<size_t>(len), 1,
                   [&](size_t j) { f(x0 + static_cast<int>(j), iy, gr[j], gpr[j]); });
  };
  int sy = static_cast<int>(floorMod(oy_ + iy0, n_));
  for (int iy = iy0; iy <= iy1; ++iy) {
    const size_t row = static_cast<size_t>(sy) * static_cast<size_t>(n_);
    run(iy, row + static_cast<size_t>(sx0), 0, before_wrap);
    run(iy, row, before_wrap, w - before_wrap);
    if (++sy == n_) sy = 0;
  }
}

template <typename F>
void AccumulativeGridMap::forEachWeightedCell(int ix0, int iy0, int ix1, int iy1, F&& f) const {
  if (!clipToWindow(ix0, iy0, ix1, iy1)) return;
  if (hits_.size() + held_.size() >= static_cast<size_t>(ix1 - ix0 + 1) * static_cast<size_t>(iy1 - iy0 + 1)) {
    forEachCell(ix0, iy0, ix1, iy1, [&f](int ix, int iy, int g, int gp) {
      if (g > 0) f(ix, iy, g, gp);
    });
    return;
  }
  for (size_t i = 0; i < hits_.size(); ++i) {
    const Hit& h = hits_[i];
    const int64_t ix = h.gx - ox_, iy = h.gy - oy_;
    if (ix < ix0 || ix > ix1 || iy < iy0 || iy > iy1) continue;
    const size_t s = slotGlobal(h.gx, h.gy);
    // Only the entry of the cell's last increment stands for it (older ones are revision
    // leftovers); a cell hit twice in that cycle has two such entries: the first one counts.
    if (g_[s] <= 0 || last_hit_[s] != h.cycle) continue;
    bool seen = false;
    for (size_t j = i; j > 0 && hits_[j - 1].cycle == h.cycle && !seen; --j)
      seen = hits_[j - 1].gx == h.gx && hits_[j - 1].gy == h.gy;
    if (!seen) f(static_cast<int>(ix), static_cast<int>(iy), g_[s], gp_[s]);
  }
  for (const Hit& h : held_) {  // one entry per cell, each its last increment's
    const int64_t ix = h.gx - ox_, iy = h.gy - oy_;
    if (ix < ix0 || ix > ix1 || iy < iy0 || iy > iy1) continue;
    const size_t s = slotGlobal(h.gx, h.gy);
    if (g_[s] > 0 && last_hit_[s] == h.cycle) f(static_cast<int>(ix), static_cast<int>(iy), g_[s], gp_[s]);
  }
}

}  // namespace lasonic
