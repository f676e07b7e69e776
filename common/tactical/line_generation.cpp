#include "tactical/line_generation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "complement/radar_map.hpp"

namespace lasonic {

LineGenerationParams lineGenerationParams(const Config& c, LineGenerationParams p) {
  c.allowOnly({"gp_threshold", "angle_bin_deg", "max_gap", "split_threshold", "min_cells", "min_length", "refit", "occlusion", "merge", "refit_cells", "refit_weights", "hidden_cells", "hidden_support"});
  p.gp_threshold = c.get("gp_threshold", p.gp_threshold, Range::between(1, 1e9));
  p.angle_bin_deg = c.get("angle_bin_deg", p.angle_bin_deg, Range{0.0, 90.0, true});
  p.max_gap = c.get("max_gap", p.max_gap, Range::positive());
  p.split_threshold = c.get("split_threshold", p.split_threshold, Range::positive());
  p.min_cells = c.get("min_cells", p.min_cells, Range::between(2, 1e6));
  p.min_length = c.get("min_length", p.min_length, Range::nonNegative());
  p.refit = c.get<bool>("refit", p.refit);
  p.merge = c.get<bool>("merge", p.merge);
  p.refit_cells = c.getChoice("refit_cells", p.refit_cells,
                              {{"run", LineGenerationParams::RefitCells::Run},
                               {"band", LineGenerationParams::RefitCells::Band}});
  p.refit_weights = c.getChoice("refit_weights", p.refit_weights,
                                {{"cells", LineGenerationParams::RefitWeights::Cells},
                                 {"echoes", LineGenerationParams::RefitWeights::Echoes}});
  p.hidden_cells = c.getChoice("hidden_cells", p.hidden_cells,
                               {{"drop", LineGenerationParams::HiddenCells::Drop},
                                {"peel", LineGenerationParams::HiddenCells::Peel}});
  p.hidden_support = c.getChoice("hidden_support", p.hidden_support,
                                 {{"shared", LineGenerationParams::HiddenSupport::Shared},
                                  {"own", LineGenerationParams::HiddenSupport::Own}});
  p.occlusion = c.getChoice("occlusion", p.occlusion,
                            {{"global", LineGenerationParams::Occlusion::Global},
                             {"per_cluster", LineGenerationParams::Occlusion::PerCluster}});
  return p;
}

std::vector<CandidateCell> candidateCells(const AccumulativeGridMap& agm, int gp_threshold,
                                          const std::function<int64_t(int64_t)>& support_of) {
  return candidateCells(agm, gp_threshold, 0, 0, agm.size(), support_of);
}

std::vector<CandidateCell> candidateCells(const AccumulativeGridMap& agm, int gp_threshold, int ix0, int iy0, int w,
                                          const std::function<int64_t(int64_t)>& support_of) {
  std::vector<CandidateCell> out;
  agm.forEachPositiveCell(ix0, iy0, ix0 + w - 1, iy0 + w - 1, [&](int ix, int iy, int g, int gp) {
    if (gp < gp_threshold) return;
    const int64_t cycle = agm.lastHitCycle(ix, iy);
    out.push_back({agm.evidencePoint(ix, iy), gp, support_of ? support_of(cycle) : cycle, g, ix, iy});
  });
  return out;
}

std::vector<PolarCell> toPolar(const std::vector<CandidateCell>& cells, const geom::Pose2& robot) {
  std::vector<PolarCell> out;
  out.reserve(cells.size());
  for (const CandidateCell& c : cells) {
    const geom::Vec2 local = robot.inverseTransform(c.centre);
    out.push_back({c, std::atan2(local.y(), local.x()), local.norm()});
  }
  return out;
}

namespace {
// Which of cells are nearest to the robot in at least one angle bin (see nearestPerAngle).
std::vector<char> nearestMask(const std::vector<PolarCell>& cells, double bin_rad, double cell_size) {
  if (cells.empty() || !(bin_rad > 0)) return std::vector<char>(cells.size(), 0);
  const int nbins = std::max(1, static_cast<int>(std::ceil(2 * geom::kPi / bin_rad)));
  constexpr size_t kNone = std::numeric_limits<size_t>::max();
  std::vector<size_t> nearest(static_cast<size_t>(nbins), kNone);
  auto binOf = [&](double a) {  // a in any range
    const double u = (a + geom::kPi) / (2 * geom::kPi);
    const double f = u - std::floor(u);
    return std::min(nbins - 1, static_cast<int>(f * nbins));
  };
  for (size_t i = 0; i < cells.size(); ++i) {
    const PolarCell& pc = cells[i];
    const double half = pc.range > 0.5 * cell_size ? std::atan2(0.5 * cell_size, pc.range) : 0.5 * geom::kPi;
    const int b0 = binOf(pc.bearing - half);
    const int span = std::min(nbins, static_cast<int>(std::ceil(2 * half / bin_rad)) + 1);
    for (int k = 0; k < span; ++k) {
      const size_t b = static_cast<size_t>((b0 + k) % nbins);
      // Bins are visited only while they overlap the cell's bearings.
      const double bin_lo = -geom::kPi + static_cast<double>(b) * bin_rad;
      if (std::abs(geom::angleDiff(bin_lo + 0.5 * bin_rad, pc.bearing)) > half + 0.5 * bin_rad) continue;
      size_t& cur = nearest[b];
      if (cur == kNone || pc.range < cells[cur].range ||
          (pc.range == cells[cur].range && pc.bearing < cells[cur].bearing))
        cur = i;
    }
  }
  std::vector<char> keep(cells.size(), 0);
  for (size_t b : nearest)
    if (b != kNone) keep[b] = 1;
  return keep;
}

// The kept cells sorted by bearing (then range).
std::vector<PolarCell> keptInBearingOrder(const std::vector<PolarCell>& cells, const std::vector<char>& keep) {
  std::vector<PolarCell> out;
  for (size_t i = 0; i < cells.size(); ++i)
    if (keep[i]) out.push_back(cells[i]);
  std::sort(out.begin(), out.end(), [](const PolarCell& a, const PolarCell& b) {
    return a.bearing != b.bearing ? a.bearing < b.bearing : a.range < b.range;
  });
  return out;
}
}  // namespace

std::vector<PolarCell> nearestPerAngle(const std::vector<PolarCell>& cells, double bin_rad, double cell_size) {
  return keptInBearingOrder(cells, nearestMask(cells, bin_rad, cell_size));
}

std::vector<std::vector<PolarCell>> splitAtGaps(const std::vector<PolarCell>& ordered, double max_gap) {
  std::vector<std::vector<PolarCell>> runs;
  const size_t n = ordered.size();
  if (n == 0) return runs;
  auto gap = [&](size_t i) {  // between i and its successor (circular)
    return (ordered[(i + 1) % n].cell.centre - ordered[i].cell.centre).norm();
  };
  size_t widest = n - 1;
  for (size_t i = 0; i < n; ++i)
    if (gap(i) > gap(widest)) widest = i;
  std::vector<PolarCell> cur;
  for (size_t k = 0; k < n; ++k) {
    const size_t i = (widest + 1 + k) % n;
    cur.push_back(ordered[i]);
    if (k + 1 == n || gap(i) > max_gap) {
      runs.push_back(std::move(cur));
      cur.clear();
    }
  }
  return runs;
}

namespace {
// Largest distance of points[r] from their total-least-squares line.
double maxResidual(const std::vector<geom::Vec2>& pts, complement::IndexRange r) {
  const complement::RmSegment s = complement::fitLine(pts, r);
  const geom::Vec2 d = s.seg.b - s.seg.a;
  const double len = d.norm();
  if (len <= 0) return 0;
  const geom::Vec2 n(-d.y() / len, d.x() / len);
  double worst = 0;
  for (size_t k = r.first; k <= r.last; ++k) worst = std::max(worst, std::abs((pts[k] - s.seg.a).dot(n)));
  return worst;
}

// Merges neighbouring pieces (they share their corner point) while the merged points fit one line
// within threshold; the pair whose merged fit is best goes first.
std::vector<complement::IndexRange> mergePieces(const std::vector<geom::Vec2>& pts,
                                                std::vector<complement::IndexRange> pieces, double threshold) {
  while (pieces.size() > 1) {
    size_t best = pieces.size();
    double best_res = threshold;
    for (size_t i = 0; i + 1 < pieces.size(); ++i) {
      const double res = maxResidual(pts, {pieces[i].first, pieces[i + 1].last});
      if (res <= best_res) {
        best_res = res;
        best = i;
      }
    }
    if (best == pieces.size()) break;
    pieces[best].last = pieces[best + 1].last;
    pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(best) + 1);
  }
  return pieces;
}
}  // namespace

namespace {
constexpr int kMaxRefitRounds = 8;

// The cells of `band` within threshold of seg (the run's fitted line), ordered along it.
std::vector<const CandidateCell*> bandCells(const geom::Segment& seg, const std::vector<CandidateCell>& band,
                                           double threshold) {
  std::vector<std::pair<double, const CandidateCell*>> near;
  const double len = seg.length();
  if (!(len > 0)) return {};
  const geom::Vec2 dir = (seg.b - seg.a) / len;
  for (const CandidateCell& c : band)
    if (geom::distance(seg, c.centre) <= threshold + 1e-6)  // a row exactly one threshold away belongs to it
      near.emplace_back((c.centre - seg.a).dot(dir), &c);
  std::sort(near.begin(), near.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<const CandidateCell*> out;
  out.reserve(near.size());
  for (const auto& n : near) out.push_back(n.second);
  return out;
}

std::vector<geom::Vec2> centres(const std::vector<const CandidateCell*>& cells) {
  std::vector<geom::Vec2> out;
  out.reserve(cells.size());
  for (const CandidateCell* c : cells) out.push_back(c->centre);
  return out;
}

// Total least squares with each cell weighted by its own G; the segment spans the projections of the
// first and last cell (cells ordered along the line). rms: weighted, as the fit.
complement::RmSegment fitWeighted(const std::vector<const CandidateCell*>& cells) {
  double wsum = 0;
  geom::Vec2 c = geom::Vec2::Zero();
  for (const CandidateCell* k : cells) {
    const double w = std::max(1, k->g);
    c += w * k->centre;
    wsum += w;
  }
  c /= wsum;
  double sxx = 0, syy = 0, sxy = 0;
  for (const CandidateCell* k : cells) {
    const double w = std::max(1, k->g);
    const geom::Vec2 d = k->centre - c;
    sxx += w * d.x() * d.x();
    syy += w * d.y() * d.y();
    sxy += w * d.x() * d.y();
  }
  const geom::Vec2 dir = geom::unitVector(geom::principalAxes(sxx, syy, sxy).angle);
  const geom::Vec2 nrm(-dir.y(), dir.x());
  double ss = 0;
  for (const CandidateCell* k : cells) ss += std::max(1, k->g) * std::pow((k->centre - c).dot(nrm), 2);
  complement::RmSegment s;
  s.seg = {c + dir * (cells.front()->centre - c).dot(dir), c + dir * (cells.back()->centre - c).dot(dir)};
  s.npoints = static_cast<int>(cells.size());
  s.rms = std::sqrt(ss / wsum);
  return s;
}
}  // namespace

std::vector<AgmLine> fitRun(const std::vector<PolarCell>& run, const LineGenerationParams& p, double cell_size,
                            const std::vector<CandidateCell>* band) {
  std::vector<AgmLine> out;
  if (run.size() < static_cast<size_t>(p.min_cells) || run.size() < 2) return out;
  std::vector<geom::Vec2> pts;
  pts.reserve(run.size());
  for (const PolarCell& c : run) pts.push_back(c.cell.centre);
  std::vector<complement::IndexRange> pieces = complement::iterativeEndPointFit(pts, {0, pts.size() - 1}, p.split_threshold);
  if (p.merge) pieces = mergePieces(pts, std::move(pieces), p.split_threshold);
  for (const complement::IndexRange& r : pieces) {
    if (r.size() < static_cast<size_t>(p.min_cells)) continue;
    AgmLine l;
    if (p.refit) {
      complement::RmSegment s = complement::fitLine(pts, r);
      if (p.refit_cells == LineGenerationParams::RefitCells::Band && band) {
        // The run's cells are always in the band (each lies within the threshold of its own fit).
        std::vector<const CandidateCell*> b = bandCells(s.seg, *band, p.split_threshold);
        if (b.size() >= r.size()) {
          if (p.refit_weights == LineGenerationParams::RefitWeights::Cells) {
            s = complement::fitLine(centres(b), {0, b.size() - 1});
          } else {
            // Chosen again around each weighted line until the band stays the same (it settles on
            // the heavy rows within a few rounds; kMaxRefitRounds bounds an oscillating band).
            for (int round = 0; round < kMaxRefitRounds; ++round) {
              s = fitWeighted(b);
              std::vector<const CandidateCell*> next = bandCells(s.seg, *band, p.split_threshold);
              if (next.size() < static_cast<size_t>(p.min_cells) || next == b) break;
              b = std::move(next);
            }
          }
        }
      }
      l.seg = s.seg;
      l.rms = s.rms;
    } else {
      l.seg = {pts[r.first], pts[r.last]};
      double ss = 0;
      for (size_t k = r.first; k <= r.last; ++k) ss += std::pow(geom::distance(l.seg, pts[k]), 2);
      l.rms = std::sqrt(ss / static_cast<double>(r.size()));
    }
    const double len = l.seg.length();
    if (len > 0) {
      const geom::Vec2 dir = (l.seg.b - l.seg.a) / len;
      l.seg.a -= 0.5 * cell_size * dir;
      l.seg.b += 0.5 * cell_size * dir;
    }
    if (l.seg.length() < p.min_length) continue;
    l.ncells = static_cast<int>(r.size());
    for (size_t k = r.first; k <= r.last; ++k) l.support = std::max(l.support, run[k].cell.support);
    out.push_back(l);
  }
  return out;
}

std::vector<std::vector<CandidateCell>> clusterCells(const std::vector<CandidateCell>& cells, double max_gap) {
  const size_t n = cells.size();
  std::vector<size_t> parent(n);
  for (size_t i = 0; i < n; ++i) parent[i] = i;
  auto find = [&](size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  // Sorted by x, so each cell is compared only with those within max_gap in x.
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return cells[a].centre.x() < cells[b].centre.x(); });
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n && cells[order[b]].centre.x() - cells[order[a]].centre.x() <= max_gap; ++b)
      if ((cells[order[a]].centre - cells[order[b]].centre).norm() <= max_gap) {
        const size_t ra = find(order[a]), rb = find(order[b]);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
      }
  std::vector<std::vector<CandidateCell>> out;
  std::vector<size_t> index(n, n);
  for (size_t i = 0; i < n; ++i) {
    const size_t r = find(i);
    if (index[r] == n) {
      index[r] = out.size();
      out.emplace_back();
    }
    out[index[r]].push_back(cells[i]);
  }
  return out;
}

namespace {
uint64_t cellKey(int ix, int iy) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(ix)) << 32) | static_cast<uint64_t>(static_cast<uint32_t>(iy));
}
bool hasIndex(const CandidateCell& c) { return c.ix != CandidateCell::kNoIndex && c.iy != CandidateCell::kNoIndex; }

// HiddenSupport::Own: the cell's Gp less the echoes of the explained cells in its neighbourhood
// still reaches G_T.
bool ownSupport(const CandidateCell& c, const std::unordered_map<uint64_t, int>& explained,
                const LineGenerationParams& p) {
  if (!hasIndex(c)) return true;
  int taken = 0;
  for (int dy = -p.neighbourhood; dy <= p.neighbourhood; ++dy)
    for (int dx = -p.neighbourhood; dx <= p.neighbourhood; ++dx)
      if (const auto it = explained.find(cellKey(c.ix + dx, c.iy + dy)); it != explained.end()) taken += it->second;
  return c.gp - taken >= p.gp_threshold;
}
}  // namespace

std::vector<LineRun> lineRuns(const std::vector<CandidateCell>& group, const geom::Pose2& robot, double cell_size,
                              const LineGenerationParams& p) {
  std::vector<LineRun> out;
  const double bin = geom::deg2rad(p.angle_bin_deg);
  std::vector<PolarCell> layer_cells = toPolar(group, robot);
  std::unordered_map<uint64_t, int> explained;  // cells a nearer layer took: their echoes (G)
  const auto explain = [&explained](const CandidateCell& c) {
    if (hasIndex(c)) explained.emplace(cellKey(c.ix, c.iy), c.g);
  };
  for (int layer = 0; layer < kMaxLineLayers && !layer_cells.empty(); ++layer) {
    const std::vector<char> keep = nearestMask(layer_cells, bin, cell_size);
    const size_t first = out.size();
    for (auto& run : splitAtGaps(keptInBearingOrder(layer_cells, keep), p.max_gap)) {
      LineRun r;
      r.lines = fitRun(run, p, cell_size, &group);
      r.cells = std::move(run);
      r.layer = layer;
      out.push_back(std::move(r));
    }
    if (p.hidden_cells == LineGenerationParams::HiddenCells::Drop) break;
    // The next layer: the hidden cells that no line of this layer took.
    std::vector<PolarCell> hidden;
    for (size_t i = 0; i < layer_cells.size(); ++i) {
      if (keep[i]) continue;
      bool taken = false;
      for (size_t k = first; k < out.size() && !taken; ++k)
        for (const AgmLine& l : out[k].lines)
          if (geom::distance(l.seg, layer_cells[i].cell.centre) <= p.split_threshold + 1e-6) {
            taken = true;
            break;
          }
      if (!taken) hidden.push_back(layer_cells[i]);
      else explain(layer_cells[i].cell);
    }
    for (size_t i = 0; i < layer_cells.size(); ++i)
      if (keep[i]) explain(layer_cells[i].cell);
    if (p.hidden_support == LineGenerationParams::HiddenSupport::Own)
      hidden.erase(std::remove_if(hidden.begin(), hidden.end(),
                                  [&](const PolarCell& h) { return !ownSupport(h.cell, explained, p); }),
                   hidden.end());
    layer_cells = std::move(hidden);
  }
  return out;
}

std::vector<AgmLine> generateLines(const std::vector<CandidateCell>& cells, const geom::Pose2& robot,
                                   double cell_size, const LineGenerationParams& p) {
  std::vector<AgmLine> out;
  auto lines = [&](const std::vector<CandidateCell>& group) {
    for (const LineRun& r : lineRuns(group, robot, cell_size, p)) out.insert(out.end(), r.lines.begin(), r.lines.end());
  };
  if (p.occlusion == LineGenerationParams::Occlusion::Global) lines(cells);
  else
    for (const auto& cluster : clusterCells(cells, p.max_gap)) lines(cluster);
  return out;
}

}  // namespace lasonic
