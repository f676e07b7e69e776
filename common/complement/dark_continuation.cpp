#include "complement/dark_continuation.hpp"

#include <algorithm>
#include <cmath>

namespace lasonic::complement {

using geom::Vec2;

namespace {

// Reading index `step` readings from i (+1 or -1), wrapping round a full circle; -1 past an end.
long neighbour(long i, long step, long n, bool full_circle) {
  const long j = i + step;
  if (j >= 0 && j < n) return j;
  if (!full_circle) return -1;
  return (j + n) % n;
}

// Continues from the return at `last` into the empty readings in direction `step`.
void continueFrom(const LaserScan& scan, const std::vector<ScanPoint>& placed, const std::vector<uint8_t>& no_return,
                  const PoseLookup& pose_at, const RadarMapConfig& rm, const DarkContinuationConfig& cfg, long last,
                  long step, std::vector<Vec2>& out) {
  const long n = static_cast<long>(placed.size());
  const bool circle = scan.full_circle;
  // The run behind the last return: returns consecutive by the Radar Map's jump rule, empty
  // readings between them skipped (a dark face flickers near its detection limit), within
  // fit_span of it.
  const Vec2 end = placed[static_cast<size_t>(last)].p;
  std::vector<Vec2> run{end};
  for (long i = last, j = neighbour(last, -step, n, circle); j >= 0 && j != last && run.size() < placed.size();
       j = neighbour(j, -step, n, circle)) {
    const ScanPoint& a = placed[static_cast<size_t>(i)];
    const ScanPoint& b = placed[static_cast<size_t>(j)];
    if (!b.valid) {
      if (no_return[static_cast<size_t>(j)] != 0) continue;  // flicker within the run
      break;
    }
    if (rangeJump(a, b, rm)) break;
    if ((b.p - end).norm() > cfg.fit_span) break;
    run.push_back(b.p);
    i = j;
  }
  if (static_cast<int>(run.size()) < rm.min_points) return;
  // The run's last straight piece, as the Radar Map's end-point fit cuts it (a corner within the
  // span ends it): the surface's direction where it was last seen.
  const std::vector<IndexRange> pieces = iterativeEndPointFit(run, IndexRange{0, run.size() - 1}, rm.split_threshold);
  IndexRange last_piece{0, 0};
  for (const IndexRange& r : pieces)
    if (r.first == 0) last_piece = r;
  if (static_cast<int>(last_piece.size()) < rm.min_points) return;
  const RmSegment line = fitLine(run, last_piece);
  const Vec2 along = line.seg.a - line.seg.b;  // from the piece's far end towards the last return
  const double length = along.norm();
  if (!(length >= rm.min_length) || !(length > 0)) return;
  const Vec2 u = along / length;
  const Vec2 normal(-u.y(), u.x());
  const Vec2 foot = line.seg.a;  // the last return's projection onto the line
  const double cos_max = std::cos(cfg.max_incidence);
  double reach = cfg.length;  // along the line from the foot
  for (long j = neighbour(last, step, n, circle); j >= 0 && j != last; j = neighbour(j, step, n, circle)) {
    if (no_return[static_cast<size_t>(j)] == 0) {
      // A return on the line (within split_threshold, farther along it) is the same surface seen
      // again: near the detection limit a dark surface flickers, a return here and there among
      // empty readings. The continuation goes on from it. Any other return, or a rejected
      // reading, ends the gap.
      const ScanPoint& q = placed[static_cast<size_t>(j)];
      if (!q.valid) return;
      const double along_q = (q.p - foot).dot(u);
      if (std::abs((q.p - foot).dot(normal)) > rm.split_threshold || !(along_q >= 0)) return;
      reach = std::max(reach, along_q + cfg.length);
      continue;
    }
    const LaserReading& r = scan.readings[static_cast<size_t>(j)];
    const auto robot = pose_at(r.utime);
    if (!robot) return;
    const geom::Pose2 sensor = robot->compose(scan.mount);
    const Vec2 o = sensor.position();
    const Vec2 d = geom::unitVector(sensor.theta + r.angle);
    // o + t d = foot + s u; the ray meets the line no more obliquely than max_incidence.
    if (std::abs(d.dot(normal)) < cos_max) return;
    const double den = d.x() * u.y() - d.y() * u.x();
    const Vec2 w = foot - o;
    const double t = (w.x() * u.y() - w.y() * u.x()) / den;
    const double s = (w.x() * d.y() - w.y() * d.x()) / den;
    if (!(t > 0) || !(s >= 0) || s > reach) return;  // behind the scanner, back along the run, or too far
    out.push_back(o + t * d);
  }
}

}  // namespace

void darkContinuation(const LaserScan& scan, const std::vector<ScanPoint>& placed,
                      const std::vector<uint8_t>& no_return, const PoseLookup& pose_at,
                      const RadarMapConfig& rm, const DarkContinuationConfig& cfg, std::vector<Vec2>& out) {
  if (!(cfg.length > 0)) return;
  const size_t n = placed.size();
  if (n < 2 || scan.readings.size() != n || no_return.size() != n) return;
  const long ln = static_cast<long>(n);
  for (long i = 0; i < ln; ++i) {
    if (!placed[static_cast<size_t>(i)].valid) continue;
    for (const long step : {+1L, -1L}) {
      const long j = neighbour(i, step, ln, scan.full_circle);
      if (j >= 0 && no_return[static_cast<size_t>(j)] != 0)
        continueFrom(scan, placed, no_return, pose_at, rm, cfg, i, step, out);
    }
  }
}

}  // namespace lasonic::complement
