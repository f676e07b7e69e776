#pragma once
// Line generation: the tactical AGM turned into lines (Jörg 1995, sec. 3.4, "Tactical
// abstraction level"). The paper's steps, each a small pure function:
//
//   candidateCells   cells whose propagated weight Gp reaches a threshold
//   toPolar          their polar coordinates in the robot's frame
//   nearestPerAngle  ordered by angle; per angle only the cells nearest to the robot (a cell
//                    covers the bearings of its width as seen from the robot, so a cell hidden
//                    behind a nearer one is dropped: the lines describe what the robot faces)
//   splitAtGaps      the ordered (circular) list cut where neighbouring cells are farther apart
//                    than max_gap, so a gap between two obstacles never becomes a line (beyond
//                    the paper's text, which leaves this to the end-point fit)
//   fitRun           iterative end-point fit along each run (the Radar Map's own
//                    iterativeEndPointFit), neighbouring pieces merged again while one line fits
//                    them (split-and-merge; beyond the paper); runs of fewer than min_cells cells
//                    dropped (isolated cells: noise); optional total-least-squares refit (on the
//                    run's cells, or on every cell of the band along the line); each end
//                    extended by half a cell, since a cell stands for the square around its centre
//   lineRuns         the runs of one group, layer by layer (cells hidden behind a layer's lines
//                    get the next layer; beyond the paper, which drops them)
//   generateLines    all of the above
// Everything is in the global (odometry) frame except the polar coordinates.
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "core/config.hpp"
#include "core/geometry.hpp"
#include "operational/agm.hpp"

namespace lasonic {

struct LineGenerationParams {
  int gp_threshold = 5;           // candidate cells: Gp >= this (the tactical G_T: every propagated cell)
  double angle_bin_deg = 1.0;     // [deg] angular resolution of "nearest per angle"
  double max_gap = 0.5;           // [m] neighbouring candidates farther apart start a new line
  double split_threshold = 0.10;  // [m] end-point fit: split while a cell centre is farther from the chord
  int min_cells = 3;              // lines fitted to fewer cells are dropped
  double min_length = 0.0;        // [m] shorter lines (after the half-cell extension) are dropped
  bool refit = true;              // total-least-squares refit of each line's cells
  // Which cells the refit uses. Run: the cells the line was fitted to (nearest per angle: the
  // paper). Band: every candidate cell of the obstacle within split_threshold of the fitted line,
  // also those behind a nearer one; an obstacle heard from both sides, or a band of cells two
  // deep, has its surface in the band's middle, not on the face nearest to the robot.
  enum class RefitCells { Run, Band } refit_cells = RefitCells::Band;
  // How the band refit weighs its cells. Cells: each cell once (every cell is one point). Echoes:
  // each cell by its own G, the echoes placed in it (not Gp: a stray cell beside a wall takes
  // the wall's echoes into its neighbourhood sum), and the band chosen again around the
  // weighted line until it no longer changes: the line is where most echoes put the surface, so
  // a few stray cells beside a two-cell-deep band (an edge's echoes placed off the surface) do
  // not tilt it.
  enum class RefitWeights { Cells, Echoes } refit_weights = RefitWeights::Echoes;
  // Split-and-merge: neighbouring pieces of a run are merged again while one line fits all their
  // cells within split_threshold (a band of cells two deep, seen at an angle, zigzags in the
  // angle order and would otherwise be split into slanted pieces).
  bool merge = true;
  // Global: the paper's rule, a cell hidden behind any nearer cell is dropped. PerCluster: only
  // behind a nearer cell of its own cluster (cells connected within max_gap), so a remembered
  // obstacle is not dropped because another one now stands in front of it.
  enum class Occlusion { Global, PerCluster } occlusion = Occlusion::PerCluster;
  // Cells hidden behind nearer ones. Drop: the paper's rule, the lines describe what the robot
  // faces. Peel: layer by layer, the hidden cells that no line of the layer took (farther than
  // split_threshold from each) get their own nearest-per-angle pass, until no cell is left: a
  // memory holds every surface it has heard, also the one behind another (a box behind a fence,
  // the far side of a railing).
  enum class HiddenCells { Drop, Peel } hidden_cells = HiddenCells::Peel;
  // What a peeled (hidden) cell must have to stay a candidate. Shared: its Gp, as every layer-0
  // cell. Own: G_T echoes in its neighbourhood that no nearer layer took: an echo
  // locates one surface, so the echoes that made the nearer surface's cells (which the contrast
  // propagation adds into every neighbour's Gp, also a stray single echo 0.1-0.2 m behind it)
  // do not confirm a second surface behind it. Needs the cells' grid indices (candidateCells
  // sets them); a cell without them keeps the shared rule.
  enum class HiddenSupport { Shared, Own } hidden_support = HiddenSupport::Own;
  int neighbourhood = 1;  // the AGM's t: Gp sums the (2t+1)^2 cells around a cell (agm.t)
};
// Reads a `lines:` section over `base`. Throws ConfigError naming the key path.
LineGenerationParams lineGenerationParams(const Config& c, LineGenerationParams base = {});

struct CandidateCell {
  geom::Vec2 centre = geom::Vec2::Zero();  // global (odometry) frame: where the cell's evidence is
  int gp = 0;           // propagated weight: the candidate test (Gp >= G_T)
  int64_t support = 0;  // when the cell was last hit (the caller's time unit, e.g. utime)
  int g = 0;            // the cell's own weight G, the echoes placed in it: the refit's weight
  // The cell's grid indices (within one map), for the neighbourhood sums of
  // LineGenerationParams::hidden_support; kNoIndex where the cell has none (hand-made cells).
  static constexpr int kNoIndex = std::numeric_limits<int>::min();
  int ix = kNoIndex;
  int iy = kNoIndex;
};

struct PolarCell {
  CandidateCell cell;
  double bearing = 0;  // [rad] robot frame, (-pi, pi]
  double range = 0;    // [m] from the robot's reference point
};

struct AgmLine {
  geom::Segment seg{geom::Vec2::Zero(), geom::Vec2::Zero()};  // global frame
  int ncells = 0;
  double rms = 0;       // [m] RMS distance of its cell centres from the line
  int64_t support = 0;  // newest support among its cells
};

// Cells with Gp >= threshold, at AccumulativeGridMap::evidencePoint (the mean of their hits with
// hit_centroids, else their centres). support_of(cycle) converts a cell's last-hit
// update cycle into the support time (identity if null).
std::vector<CandidateCell> candidateCells(const AccumulativeGridMap& agm, int gp_threshold,
                                          const std::function<int64_t(int64_t cycle)>& support_of = nullptr);
// The same within the w x w sub-window whose cell (0, 0) is window cell (ix0, iy0).
std::vector<CandidateCell> candidateCells(const AccumulativeGridMap& agm, int gp_threshold, int ix0, int iy0, int w,
                                          const std::function<int64_t(int64_t cycle)>& support_of = nullptr);

std::vector<PolarCell> toPolar(const std::vector<CandidateCell>& cells, const geom::Pose2& robot);

// The cells nearest to the robot in at least one angle bin (bin_rad wide), each cell covering
// the bearings within atan((cell_size/2) / range) of its own; sorted by bearing.
std::vector<PolarCell> nearestPerAngle(const std::vector<PolarCell>& cells, double bin_rad, double cell_size);

// Cuts the bearing-ordered circular list into runs at every gap wider than max_gap (distance
// between consecutive cell centres). The list is rotated to start after its widest gap, so an
// obstacle behind the robot is not cut at the bearing seam.
std::vector<std::vector<PolarCell>> splitAtGaps(const std::vector<PolarCell>& ordered, double max_gap);

// Groups cells into clusters: cells whose centres are at most max_gap apart are in one cluster
// (single linkage). Clusters in order of their first cell.
std::vector<std::vector<CandidateCell>> clusterCells(const std::vector<CandidateCell>& cells, double max_gap);

// The lines of one run: iterative end-point fit, min_cells, optional refit, ends extended by
// cell_size/2.
// band: the candidate cells a RefitCells::Band refit may use (null: the run's own).
std::vector<AgmLine> fitRun(const std::vector<PolarCell>& run, const LineGenerationParams& p, double cell_size,
                            const std::vector<CandidateCell>* band = nullptr);

// One run of cells and the lines fitted to it; layer 0 is what the robot faces.
struct LineRun {
  std::vector<PolarCell> cells;
  std::vector<AgmLine> lines;
  int layer = 0;
};
// The runs of one group of cells (a cluster, or all cells with global occlusion): nearest per
// angle, cut at gaps, fitted (the band refit draws on the whole group); with HiddenCells::Peel
// the next layers as described there (at most kMaxLineLayers; a blob of cells that deep is no
// surface).
constexpr int kMaxLineLayers = 32;
std::vector<LineRun> lineRuns(const std::vector<CandidateCell>& group, const geom::Pose2& robot, double cell_size,
                              const LineGenerationParams& p);

std::vector<AgmLine> generateLines(const std::vector<CandidateCell>& cells, const geom::Pose2& robot,
                                   double cell_size, const LineGenerationParams& p);

}  // namespace lasonic
