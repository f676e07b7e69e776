#include "complement/radar_map.hpp"

#include "core/pose_history.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
// The AVX2 loops (placement, jump test, end-point fit): compiled on x86-64 whatever the build's
// baseline (a function attribute), run only where the CPU has AVX2 (asked at run time).
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define LASONIC_AVX2_LOOP 1
#define LASONIC_AVX2 __attribute__((target("avx2")))  // not "fma": a fused a * b + c rounds once
#else
#define LASONIC_AVX2_LOOP 0
#endif

namespace lasonic::complement {

using geom::Vec2;

namespace {
// Pose2::transform with cos/sin computed only when the angle changes (bit for bit the same
// values: the mount's angle is the same for a whole scan, the robot's while it does not turn).
class CachedRotation {
 public:
  Vec2 transform(const geom::Pose2& f, const Vec2& l) {
    use(f.theta);
    return {f.x + c_ * l.x() - s_ * l.y(), f.y + s_ * l.x() + c_ * l.y()};
  }
  // The cos and sin transform(f, l) uses for f.theta == theta: c(), s().
  void use(double theta) {
    if (std::memcmp(&theta, &theta_, sizeof theta_) != 0) {
      theta_ = theta;
      c_ = std::cos(theta_);
      s_ = std::sin(theta_);
    }
  }
  double c() const { return c_; }
  double s() const { return s_; }

 private:
  double theta_ = std::numeric_limits<double>::quiet_NaN(), c_ = 0, s_ = 0;
};


// cos/sin of each reading's angle, kept from the previous scan: a scanner's angles are the same
// scan after scan, and a value is reused only for the very same angle (bit for bit). Kept as
// three arrays, so that a whole scan's angles are checked four at a time and the directions
// loaded four at a time.
class UnitVectors {
 public:
  Vec2 at(size_t i, double angle) {
    if (i >= angle_.size()) grow(i + 1);
    refresh(i, angle);
    return {ux_[i], uy_[i]};
  }
  // After prepare(r, n): ux()[i], uy()[i] hold at(i, r[i].angle) for every i < n (every
  // reading's angle, valid or not: each is then the same bits from scan to scan).
  void prepare(const LaserReading* r, size_t n) {
    if (n > angle_.size()) grow(n);
    size_t i = 0;
#if LASONIC_AVX2_LOOP
    if (vectorPath() == VectorPath::Avx2) i = sameAnglesAvx2(r, n);
#endif
    for (; i < n; ++i) refresh(i, r[i].angle);
  }
  const double* ux() const { return ux_.data(); }
  const double* uy() const { return uy_.data(); }

 private:
  void grow(size_t n) {
    angle_.resize(n, std::numeric_limits<double>::quiet_NaN());
    ux_.resize(n, 0.0);
    uy_.resize(n, 0.0);
  }
  void refresh(size_t i, double angle) {
    if (std::memcmp(&angle_[i], &angle, sizeof angle) == 0) return;
    const Vec2 u = geom::unitVector(angle);
    angle_[i] = angle, ux_[i] = u.x(), uy_[i] = u.y();
  }
#if LASONIC_AVX2_LOOP
  // prepare() four at a time: quads whose angles all equal the kept ones (bit for bit) are
  // skipped, the others refreshed one by one; returns how many readings it did.
  LASONIC_AVX2 size_t sameAnglesAvx2(const LaserReading* r, size_t n) {
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
      const __m256i now = _mm256_castpd_si256(_mm256_set_pd(r[i + 3].angle, r[i + 2].angle, r[i + 1].angle, r[i].angle));
      const __m256i kept = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(angle_.data() + i));
      if (_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(now, kept))) != 0xF)
        for (size_t k = i; k < i + 4; ++k) refresh(k, r[k].angle);
    }
    return i;
  }
#endif
  std::vector<double> angle_, ux_, uy_;
};
}  // namespace

namespace {
// Reading -> global point; pose_at(utime) -> std::optional<geom::Pose2>.
template <typename PoseAt>
std::vector<ScanPoint> placeWith(const LaserScan& scan, PoseAt&& pose_at, int* no_pose) {
  std::vector<ScanPoint> out(scan.readings.size());
  int missing = 0;
  CachedRotation mount_rot, robot_rot;
  thread_local UnitVectors unit;  // a memo only: the result depends on the arguments alone
  for (size_t i = 0; i < scan.readings.size(); ++i) {
    const LaserReading& r = scan.readings[i];
    if (!r.valid) continue;
    const auto robot = pose_at(r.utime);
    if (!robot) {
      ++missing;
      continue;
    }
    const Vec2 local = mount_rot.transform(scan.mount, r.range * unit.at(i, r.angle));
    out[i] = {robot_rot.transform(*robot, local), r.range, true};
  }
  if (no_pose) *no_pose = missing;
  return out;
}
}  // namespace

std::vector<ScanPoint> placeReadings(const LaserScan& scan, const PoseLookup& pose_at, int* no_pose) {
  return placeWith(scan, pose_at, no_pose);
}

namespace {
VectorPath widestPath() {
#if LASONIC_AVX2_LOOP
  __builtin_cpu_init();  // (in case this runs before the constructors)
  if (__builtin_cpu_supports("avx2")) return VectorPath::Avx2;
#endif
#if defined(__SSE2__)
  return VectorPath::Sse2;
#else
  return VectorPath::Scalar;
#endif
}

std::atomic<VectorPath>& pathInUse() {
  static std::atomic<VectorPath> path{widestPath()};  // the CPU asked once
  return path;
}
}  // namespace

void setVectorPath(VectorPath widest) { pathInUse().store(std::min(widest, widestPath()), std::memory_order_relaxed); }
VectorPath vectorPath() { return pathInUse().load(std::memory_order_relaxed); }

namespace {
// placeReadings' vector loops: W readings of one odometry interval at a time, where the cursor
// interpolates there by the series (PoseHistory::Cursor::seriesAt). Each lane does the scalar
// loop's operations on one reading, in the same order and rounded the same way (no fused
// multiply-add: the AVX2 loop is compiled for "avx2" alone), so every value is the scalar one.
//   f = double(t - lo) / den, phi = f * dtheta, q = phi * phi, the series sp and cp,
//   c = ca * cp - sa * sp, s = sa * cp + ca * sp, robot (ax + f * dx, ay + f * dy),
//   out = (rx + c * lx - s * ly, ry + s * lx + c * ly), (lx, ly) the reading in the robot frame.
using Cursor = PoseHistory::Cursor;

// Readings i .. i + w - 1 are valid and inside the cursor's interval, which interpolates by the
// series (entered for reading i if needed).
inline bool lanesInInterval(Cursor& cursor, const LaserReading* r, size_t w) {
  if (!r[0].valid || !cursor.seriesAt(r[0].utime)) return false;
  for (size_t k = 0; k < w; ++k)
    if (!r[k].valid || !(cursor.lo() < r[k].utime && r[k].utime <= cursor.hi())) return false;
  return true;
}

#if defined(__SSE2__)
void placeTwoSse2(const Cursor& cu, const LaserReading* r, const double* lx, const double* ly, ScanPoint* out) {
  const __m128d f = _mm_div_pd(_mm_set_pd(static_cast<double>(r[1].utime - cu.lo()),
                                          static_cast<double>(r[0].utime - cu.lo())),
                               _mm_set1_pd(cu.den()));
  const __m128d phi = _mm_mul_pd(f, _mm_set1_pd(cu.dtheta()));
  const __m128d rx = _mm_add_pd(_mm_set1_pd(cu.ax()), _mm_mul_pd(f, _mm_set1_pd(cu.dx())));
  const __m128d ry = _mm_add_pd(_mm_set1_pd(cu.ay()), _mm_mul_pd(f, _mm_set1_pd(cu.dy())));
  const __m128d q = _mm_mul_pd(phi, phi);
  const auto k = [](double v) { return _mm_set1_pd(v); };
  __m128d ps = _mm_add_pd(k(Cursor::s9), _mm_mul_pd(q, k(Cursor::s11)));
  ps = _mm_add_pd(k(Cursor::s7), _mm_mul_pd(q, ps));
  ps = _mm_add_pd(k(Cursor::s5), _mm_mul_pd(q, ps));
  ps = _mm_add_pd(k(Cursor::s3), _mm_mul_pd(q, ps));
  const __m128d sp = _mm_add_pd(phi, _mm_mul_pd(_mm_mul_pd(phi, q), ps));
  __m128d pc = _mm_add_pd(k(Cursor::c8), _mm_mul_pd(q, k(Cursor::c10)));
  pc = _mm_add_pd(k(Cursor::c6), _mm_mul_pd(q, pc));
  pc = _mm_add_pd(k(Cursor::c4), _mm_mul_pd(q, pc));
  pc = _mm_add_pd(k(Cursor::c2), _mm_mul_pd(q, pc));
  const __m128d cp = _mm_add_pd(k(1.0), _mm_mul_pd(q, pc));
  const __m128d ca = k(cu.ca()), sa = k(cu.sa());
  const __m128d c = _mm_sub_pd(_mm_mul_pd(ca, cp), _mm_mul_pd(sa, sp));
  const __m128d s = _mm_add_pd(_mm_mul_pd(sa, cp), _mm_mul_pd(ca, sp));
  const __m128d x = _mm_loadu_pd(lx), y = _mm_loadu_pd(ly);
  const __m128d ox = _mm_sub_pd(_mm_add_pd(rx, _mm_mul_pd(c, x)), _mm_mul_pd(s, y));
  const __m128d oy = _mm_add_pd(_mm_add_pd(ry, _mm_mul_pd(s, x)), _mm_mul_pd(c, y));
  _mm_storeu_pd(out[0].p.data(), _mm_unpacklo_pd(ox, oy));
  _mm_storeu_pd(out[1].p.data(), _mm_unpackhi_pd(ox, oy));
  for (size_t j = 0; j < 2; ++j) out[j].range = r[j].range, out[j].valid = true;
}
#endif

#if LASONIC_AVX2_LOOP
LASONIC_AVX2 void placeFourAvx2(const Cursor& cu, const LaserReading* r, const double* lx, const double* ly,
                                ScanPoint* out) {
  const __m256d f = _mm256_div_pd(
      _mm256_set_pd(static_cast<double>(r[3].utime - cu.lo()), static_cast<double>(r[2].utime - cu.lo()),
                    static_cast<double>(r[1].utime - cu.lo()), static_cast<double>(r[0].utime - cu.lo())),
      _mm256_set1_pd(cu.den()));
  const __m256d phi = _mm256_mul_pd(f, _mm256_set1_pd(cu.dtheta()));
  const __m256d rx = _mm256_add_pd(_mm256_set1_pd(cu.ax()), _mm256_mul_pd(f, _mm256_set1_pd(cu.dx())));
  const __m256d ry = _mm256_add_pd(_mm256_set1_pd(cu.ay()), _mm256_mul_pd(f, _mm256_set1_pd(cu.dy())));
  const __m256d q = _mm256_mul_pd(phi, phi);
  __m256d ps = _mm256_add_pd(_mm256_set1_pd(Cursor::s9), _mm256_mul_pd(q, _mm256_set1_pd(Cursor::s11)));
  ps = _mm256_add_pd(_mm256_set1_pd(Cursor::s7), _mm256_mul_pd(q, ps));
  ps = _mm256_add_pd(_mm256_set1_pd(Cursor::s5), _mm256_mul_pd(q, ps));
  ps = _mm256_add_pd(_mm256_set1_pd(Cursor::s3), _mm256_mul_pd(q, ps));
  const __m256d sp = _mm256_add_pd(phi, _mm256_mul_pd(_mm256_mul_pd(phi, q), ps));
  __m256d pc = _mm256_add_pd(_mm256_set1_pd(Cursor::c8), _mm256_mul_pd(q, _mm256_set1_pd(Cursor::c10)));
  pc = _mm256_add_pd(_mm256_set1_pd(Cursor::c6), _mm256_mul_pd(q, pc));
  pc = _mm256_add_pd(_mm256_set1_pd(Cursor::c4), _mm256_mul_pd(q, pc));
  pc = _mm256_add_pd(_mm256_set1_pd(Cursor::c2), _mm256_mul_pd(q, pc));
  const __m256d cp = _mm256_add_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(q, pc));
  const __m256d ca = _mm256_set1_pd(cu.ca()), sa = _mm256_set1_pd(cu.sa());
  const __m256d c = _mm256_sub_pd(_mm256_mul_pd(ca, cp), _mm256_mul_pd(sa, sp));
  const __m256d s = _mm256_add_pd(_mm256_mul_pd(sa, cp), _mm256_mul_pd(ca, sp));
  const __m256d x = _mm256_loadu_pd(lx), y = _mm256_loadu_pd(ly);
  const __m256d ox = _mm256_sub_pd(_mm256_add_pd(rx, _mm256_mul_pd(c, x)), _mm256_mul_pd(s, y));
  const __m256d oy = _mm256_add_pd(_mm256_add_pd(ry, _mm256_mul_pd(s, x)), _mm256_mul_pd(c, y));
  const __m256d even = _mm256_unpacklo_pd(ox, oy), odd = _mm256_unpackhi_pd(ox, oy);  // (x0 y0 x2 y2), (x1 y1 x3 y3)
  _mm_storeu_pd(out[0].p.data(), _mm256_castpd256_pd128(even));
  _mm_storeu_pd(out[1].p.data(), _mm256_castpd256_pd128(odd));
  _mm_storeu_pd(out[2].p.data(), _mm256_extractf128_pd(even, 1));
  _mm_storeu_pd(out[3].p.data(), _mm256_extractf128_pd(odd, 1));
  for (size_t j = 0; j < 4; ++j) out[j].range = r[j].range, out[j].valid = true;
}

// placeReadings' first loop, four readings at a time: each lane the scalar operations on one
// reading (x = range * ux, y = range * uy, lx = mx + mc * x - ms * y, ly = my + ms * x + mc * y,
// left to right); returns how many readings it did (a multiple of four).
LASONIC_AVX2 size_t robotFrameAvx2(const LaserReading* rd, const double* ux, const double* uy, size_t n, double mc,
                                   double ms, double mx, double my, double* lx, double* ly) {
  const __m256d vmc = _mm256_set1_pd(mc), vms = _mm256_set1_pd(ms), vmx = _mm256_set1_pd(mx), vmy = _mm256_set1_pd(my);
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d r = _mm256_set_pd(rd[i + 3].range, rd[i + 2].range, rd[i + 1].range, rd[i].range);
    const __m256d x = _mm256_mul_pd(r, _mm256_loadu_pd(ux + i)), y = _mm256_mul_pd(r, _mm256_loadu_pd(uy + i));
    _mm256_storeu_pd(lx + i, _mm256_sub_pd(_mm256_add_pd(vmx, _mm256_mul_pd(vmc, x)), _mm256_mul_pd(vms, y)));
    _mm256_storeu_pd(ly + i, _mm256_add_pd(_mm256_add_pd(vmy, _mm256_mul_pd(vms, x)), _mm256_mul_pd(vmc, y)));
  }
  return i;
}
#endif
}  // namespace

std::vector<ScanPoint> placeReadings(const LaserScan& scan, const PoseHistory& poses, int* no_pose) {
  std::vector<ScanPoint> out;
  placeReadingsInto(scan, poses, out, no_pose);
  return out;
}

void placeReadingsInto(const LaserScan& scan, const PoseHistory& poses, std::vector<ScanPoint>& out, int* no_pose) {
  // As placeWith, with the robot's rotation from the cursor (angle addition while it turns).
  const size_t n = scan.readings.size();
  out.resize(n);  // (every element is written below: what an earlier call left does not matter)
  // First each valid reading in the robot frame (the mount's rotation and the reading's own
  // direction do not depend on the pose), then each placed with its pose.
  thread_local UnitVectors unit;  // a memo only: the result depends on the arguments alone
  thread_local std::vector<double> lx, ly;  // (scratch)
  lx.resize(n);
  ly.resize(n);
  CachedRotation mount_rot;  // (CachedRotation::transform's values, its cos and sin taken once)
  mount_rot.use(scan.mount.theta);
  const double mc = mount_rot.c(), ms = mount_rot.s(), mx = scan.mount.x, my = scan.mount.y;
  const LaserReading* rd = scan.readings.data();
  unit.prepare(rd, n);
  const double* ux = unit.ux();
  const double* uy = unit.uy();
  size_t i0 = 0;
#if LASONIC_AVX2_LOOP
  if (vectorPath() == VectorPath::Avx2) i0 = robotFrameAvx2(rd, ux, uy, n, mc, ms, mx, my, lx.data(), ly.data());
#endif
  for (size_t i = i0; i < n; ++i) {
    // mount_rot.transform(scan.mount, range * u), for valid readings (others: not used)
    const double x = rd[i].range * ux[i], y = rd[i].range * uy[i];
    lx[i] = mx + mc * x - ms * y;
    ly[i] = my + ms * x + mc * y;
  }
  int missing = 0;
  PoseHistory::Cursor cursor(poses);
  const VectorPath path = vectorPath();
  for (size_t i = 0; i < n;) {
#if LASONIC_AVX2_LOOP
    if (path == VectorPath::Avx2 && i + 4 <= n && lanesInInterval(cursor, rd + i, 4)) {
      placeFourAvx2(cursor, rd + i, lx.data() + i, ly.data() + i, out.data() + i);
      i += 4;
      continue;
    }
#endif
#if defined(__SSE2__)
    if (path != VectorPath::Scalar && i + 2 <= n && lanesInInterval(cursor, rd + i, 2)) {
      placeTwoSse2(cursor, rd + i, lx.data() + i, ly.data() + i, out.data() + i);
      i += 2;
      continue;
    }
#endif
    const LaserReading& r = rd[i];
    out[i] = ScanPoint{};
    if (r.valid) {
      double c = 1, s = 0;
      if (const auto robot = cursor.atRotated(r.utime, c, s))
        out[i] = {Vec2(robot->x + c * lx[i] - s * ly[i], robot->y + s * lx[i] + c * ly[i]), r.range, true};
      else
        ++missing;
    }
    ++i;
  }
  if (no_pose) *no_pose = missing;
}

namespace {
// std::sqrt(d2) > t, decided on d2 against t * t where that is safe. sqrt is correctly rounded, so
// outside a relative band of 2^-48 around t * t (both roundings are within 2^-52 of it) the
// squares decide as the roots would; inside it, and for NaN, the root itself.
inline bool rootGreater(double d2, double t) {
  if (!(t > 1e-150 && t < 1e150)) return std::sqrt(d2) > t;  // (t * t neither underflows nor overflows)
  const double t2 = t * t;
  if (d2 > t2 * (1.0 + 0x1p-48)) return true;
  if (d2 < t2 * (1.0 - 0x1p-48)) return false;
  return std::sqrt(d2) > t;
}

// A range jump: the threshold grows with range because neighbouring rays diverge.
bool isJump(const ScanPoint& a, const ScanPoint& b, const RadarMapConfig& cfg) {
  // (a.p - b.p).norm() > threshold
  return rootGreater((a.p - b.p).squaredNorm(), cfg.jump_abs + cfg.jump_rel * std::min(a.range, b.range));
}

// Point b cannot continue the cluster of point a, its predecessor.
inline bool breakBetween(const ScanPoint& a, const ScanPoint& b, const RadarMapConfig& cfg) {
  return !a.valid || !b.valid || isJump(a, b, cfg);
}

// The jump test's vector loops: W neighbouring pairs at a time, each lane rootGreater's
// operations on one pair (d2 = dx * dx + dy * dy, t = jump_abs + jump_rel * min(range), the
// squares against t * t (1 +- 2^-48)); a lane the squares leave undecided (t outside
// (1e-150, 1e150), d2 within the band or NaN) and a lane with an invalid point go the scalar
// way. _mm_min_pd(b, a) is std::min(a, b) (b < a ? b : a) whatever the values.
#if defined(__SSE2__)
// brk[k] = breakBetween(p[k - 1], p[k]) for k = 1, 2; returns false (nothing written) if a lane
// needs the scalar test.
inline bool twoBreaksSse2(const ScanPoint* p, const RadarMapConfig& cfg, uint8_t* brk) {
  const __m128d p0 = _mm_loadu_pd(p[0].p.data()), p1 = _mm_loadu_pd(p[1].p.data()), p2 = _mm_loadu_pd(p[2].p.data());
  const __m128d dx = _mm_sub_pd(_mm_unpacklo_pd(p0, p1), _mm_unpacklo_pd(p1, p2));
  const __m128d dy = _mm_sub_pd(_mm_unpackhi_pd(p0, p1), _mm_unpackhi_pd(p1, p2));
  const __m128d d2 = _mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy));
  const __m128d ra = _mm_set_pd(p[1].range, p[0].range), rb = _mm_set_pd(p[2].range, p[1].range);
  const __m128d t = _mm_add_pd(_mm_set1_pd(cfg.jump_abs), _mm_mul_pd(_mm_set1_pd(cfg.jump_rel), _mm_min_pd(rb, ra)));
  const __m128d t2 = _mm_mul_pd(t, t);
  const __m128d above = _mm_cmpgt_pd(d2, _mm_mul_pd(t2, _mm_set1_pd(1.0 + 0x1p-48)));
  const __m128d below = _mm_cmplt_pd(d2, _mm_mul_pd(t2, _mm_set1_pd(1.0 - 0x1p-48)));
  const __m128d safe = _mm_and_pd(_mm_cmpgt_pd(t, _mm_set1_pd(1e-150)), _mm_cmplt_pd(t, _mm_set1_pd(1e150)));
  const int decided = _mm_movemask_pd(_mm_and_pd(safe, _mm_or_pd(above, below)));
  if (decided != 3 || !(p[0].valid && p[1].valid && p[2].valid)) return false;
  const int jump = _mm_movemask_pd(above);
  brk[1] = static_cast<uint8_t>(jump & 1);
  brk[2] = static_cast<uint8_t>((jump >> 1) & 1);
  return true;
}
#endif

#if LASONIC_AVX2_LOOP
// brk[k] = breakBetween(p[k - 1], p[k]) for k = 1 .. 4, as twoBreaksSse2.
LASONIC_AVX2 bool fourBreaksAvx2(const ScanPoint* p, const RadarMapConfig& cfg, uint8_t* brk) {
  // (x0 y0 x2 y2), (x1 y1 x3 y3), (x2 y2 x4 y4): the x and y of points 0-3 and of points 1-4.
  const __m256d a = _mm256_set_m128d(_mm_loadu_pd(p[2].p.data()), _mm_loadu_pd(p[0].p.data()));
  const __m256d b = _mm256_set_m128d(_mm_loadu_pd(p[3].p.data()), _mm_loadu_pd(p[1].p.data()));
  const __m256d c = _mm256_set_m128d(_mm_loadu_pd(p[4].p.data()), _mm_loadu_pd(p[2].p.data()));
  const __m256d dx = _mm256_sub_pd(_mm256_unpacklo_pd(a, b), _mm256_unpacklo_pd(b, c));
  const __m256d dy = _mm256_sub_pd(_mm256_unpackhi_pd(a, b), _mm256_unpackhi_pd(b, c));
  const __m256d d2 = _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy));
  const __m256d ra = _mm256_set_pd(p[3].range, p[2].range, p[1].range, p[0].range);
  const __m256d rb = _mm256_set_pd(p[4].range, p[3].range, p[2].range, p[1].range);
  const __m256d t = _mm256_add_pd(_mm256_set1_pd(cfg.jump_abs),
                                  _mm256_mul_pd(_mm256_set1_pd(cfg.jump_rel), _mm256_min_pd(rb, ra)));
  const __m256d t2 = _mm256_mul_pd(t, t);
  const __m256d above = _mm256_cmp_pd(d2, _mm256_mul_pd(t2, _mm256_set1_pd(1.0 + 0x1p-48)), _CMP_GT_OS);
  const __m256d below = _mm256_cmp_pd(d2, _mm256_mul_pd(t2, _mm256_set1_pd(1.0 - 0x1p-48)), _CMP_LT_OS);
  const __m256d safe = _mm256_and_pd(_mm256_cmp_pd(t, _mm256_set1_pd(1e-150), _CMP_GT_OS),
                                     _mm256_cmp_pd(t, _mm256_set1_pd(1e150), _CMP_LT_OS));
  const int decided = _mm256_movemask_pd(_mm256_and_pd(safe, _mm256_or_pd(above, below)));
  if (decided != 15 || !(p[0].valid && p[1].valid && p[2].valid && p[3].valid && p[4].valid)) return false;
  const int jump = _mm256_movemask_pd(above);
  for (int k = 0; k < 4; ++k) brk[k + 1] = static_cast<uint8_t>((jump >> k) & 1);
  return true;
}
#endif

// brk[i] = breakBetween(points[i - 1], points[i]) for 1 <= i < n.
void jumpBreaks(const ScanPoint* points, size_t n, const RadarMapConfig& cfg, uint8_t* brk) {
  const VectorPath path = vectorPath();
  size_t i = 1;  // the next pair (i - 1, i)
  while (i < n) {
#if LASONIC_AVX2_LOOP
    if (path == VectorPath::Avx2 && i + 4 <= n && fourBreaksAvx2(points + i - 1, cfg, brk + i - 1)) {
      i += 4;
      continue;
    }
#endif
#if defined(__SSE2__)
    if (path != VectorPath::Scalar && i + 2 <= n && twoBreaksSse2(points + i - 1, cfg, brk + i - 1)) {
      i += 2;
      continue;
    }
#endif
    brk[i] = breakBetween(points[i - 1], points[i], cfg);
    ++i;
  }
}
}  // namespace

bool rangeJump(const ScanPoint& a, const ScanPoint& b, const RadarMapConfig& cfg) { return isJump(a, b, cfg); }

namespace {
// The clusters of splitClusters, flat: cluster k is flat[starts[k] .. starts[k + 1]) (no vector
// per cluster: a scan has dozens). `closed`: the one cluster of a full circle without a break.
struct FlatClusters {
  std::vector<Vec2> flat;
  std::vector<size_t> starts;  // one per cluster, and the end
  bool closed = false;
  size_t size() const { return starts.empty() ? 0 : starts.size() - 1; }
  size_t first(size_t k) const { return starts[k]; }
  size_t count(size_t k) const { return starts[k + 1] - starts[k]; }
};

void splitClustersFlat(const std::vector<ScanPoint>& points, bool full_circle, const RadarMapConfig& cfg,
                       FlatClusters& out) {
  const size_t n = points.size();
  out.flat.clear();
  out.starts.clear();
  out.closed = false;
  if (n == 0) return;
  // brk[i]: point i cannot continue the cluster of point i-1 (of the last point for i = 0).
  thread_local std::vector<uint8_t> brk;  // (scratch)
  brk.resize(n);
  brk[0] = !full_circle || breakBetween(points[n - 1], points[0], cfg);
  jumpBreaks(points.data(), n, cfg, brk.data());
  // Start at a break so that a cluster spanning the end of a full circle stays whole.
  std::optional<size_t> start;
  for (size_t i = 0; i < n && !start; ++i)
    if (brk[i]) start = i;
  out.flat.reserve(n);
  out.starts.push_back(0);
  if (!start) {  // a full circle without a single break
    for (const ScanPoint& p : points) out.flat.push_back(p.p);
    out.starts.push_back(n);
    out.closed = true;
    return;
  }
  // Each run from a break to the next (the last one on round the end to the first break) is a
  // cluster: a point without a break before it is valid and so is its predecessor, so a run's
  // points are all valid -- but for a run of one invalid point, which gives no cluster.
  size_t s = *start;
  while (true) {
    const void* hit = s + 1 < n ? std::memchr(brk.data() + s + 1, 1, n - s - 1) : nullptr;
    const size_t e = hit ? static_cast<size_t>(static_cast<const uint8_t*>(hit) - brk.data()) : n;
    const size_t len = e - s + (e == n ? *start : 0);
    if (points[s].valid) {
      for (size_t k = 0, i = s; k < len; ++k, i = i + 1 == n ? 0 : i + 1) out.flat.push_back(points[i].p);
      out.starts.push_back(out.flat.size());
    }
    if (e == n) break;
    s = e;
  }
}
}  // namespace

std::vector<Cluster> splitClusters(const std::vector<ScanPoint>& points, bool full_circle,
                                   const RadarMapConfig& cfg) {
  FlatClusters fc;
  splitClustersFlat(points, full_circle, cfg, fc);
  std::vector<Cluster> clusters(fc.size());
  for (size_t k = 0; k < fc.size(); ++k) {
    const auto* b = fc.flat.data() + fc.first(k);
    clusters[k].points.assign(b, b + fc.count(k));
    clusters[k].closed = fc.closed;
  }
  return clusters;
}

namespace {
// geom::distance(chord, p) for many points p: the chord's direction and squared length once
// (the same operations as closestPoint, so the same values).
class ChordDistance {
 public:
  explicit ChordDistance(const geom::Segment& s) : a_(s.a), e_(s.b - s.a), l2_(e_.squaredNorm()) {}
  // The square of the distance (norm() is the root of squaredNorm()).
  double squared(const Vec2& p) const {
    if (l2_ <= 0.0) return (a_ - p).squaredNorm();
    const double u = std::clamp((p - a_).dot(e_) / l2_, 0.0, 1.0);
    const Vec2 closest = a_ + u * e_;
    return (closest - p).squaredNorm();
  }
  // out[k] = squared(p[k]) for k < count.
  void squaredMany(const Vec2* p, size_t count, double* out) const;
  // The end-point fit's choice over p[0 .. count-1] in order, from the leader (m2, at): a point
  // takes over when its square is larger and so is its root (takeOver).
  void farthest(const Vec2* p, size_t count, double& m2, size_t& at) const;

 private:
  Vec2 a_, e_;
  double l2_;
};

// sqrt(d2) > sqrt(m2) for d2 > m2 >= 0: on the squares unless they are within 2^-48 (then both
// roots may round to the same double).
inline bool rootOfLarger(double d2, double m2) {
  return d2 > m2 * (1.0 + 0x1p-48) || std::sqrt(d2) > std::sqrt(m2);
}

// Point k, at squared distance d2, becomes the leader (m2, at): the first point farthest from the
// chord, a later one only if its distance (the root) is larger. m2 < 0: none yet; NaN never.
inline void takeOver(double d2, size_t k, double& m2, size_t& at) {
  if (d2 > m2 && (m2 < 0 || rootOfLarger(d2, m2))) {
    m2 = d2;
    at = k;
  }
}

// squared()'s vector loops, each lane its operations on one point in the same order: w = p - a,
// u = clamp((w.x e.x + w.y e.y) / l2, 0, 1) (_mm_max_pd(0, v) is std::max(v, 0) and
// _mm_min_pd(1, t) std::min(t, 1), whatever the values), c = a + u e, (c.x - p.x)^2 + (c.y - p.y)^2.
// Only for l2 > 0 or NaN (the other branch goes the scalar way). The choice goes on lane by lane
// in order where a lane's square is larger than the leader's; none is, none can take over.
#if defined(__SSE2__)
inline __m128d chordSquaresSse2(__m128d x, __m128d y, const double* k) {  // k: ax ay ex ey l2
  const __m128d ax = _mm_set1_pd(k[0]), ay = _mm_set1_pd(k[1]), ex = _mm_set1_pd(k[2]), ey = _mm_set1_pd(k[3]);
  const __m128d dot = _mm_add_pd(_mm_mul_pd(_mm_sub_pd(x, ax), ex), _mm_mul_pd(_mm_sub_pd(y, ay), ey));
  const __m128d u = _mm_min_pd(_mm_set1_pd(1.0), _mm_max_pd(_mm_setzero_pd(), _mm_div_pd(dot, _mm_set1_pd(k[4]))));
  const __m128d cx = _mm_sub_pd(_mm_add_pd(ax, _mm_mul_pd(u, ex)), x);
  const __m128d cy = _mm_sub_pd(_mm_add_pd(ay, _mm_mul_pd(u, ey)), y);
  return _mm_add_pd(_mm_mul_pd(cx, cx), _mm_mul_pd(cy, cy));
}
inline __m128d chordSquaresSse2(const Vec2* p, const double* k) {  // p[0], p[1]
  const __m128d a = _mm_loadu_pd(p[0].data()), b = _mm_loadu_pd(p[1].data());
  return chordSquaresSse2(_mm_unpacklo_pd(a, b), _mm_unpackhi_pd(a, b), k);
}
#endif
#if LASONIC_AVX2_LOOP
// kExact: u = dot / l2 as squared() takes it; otherwise u = dot * inv_l2 (no division: the
// loop's bottleneck), a square only a few units in the last place away (screenedFarthestAvx2).
template <bool kExact>
LASONIC_AVX2 inline __m256d chordSquaresAvx2(const Vec2* p, const double* k, __m256d inv_l2) {  // p[0 .. 3]
  const __m256d ax = _mm256_set1_pd(k[0]), ay = _mm256_set1_pd(k[1]), ex = _mm256_set1_pd(k[2]),
                ey = _mm256_set1_pd(k[3]);
  // (x0 y0 x2 y2), (x1 y1 x3 y3) -> (x0 x1 x2 x3), (y0 y1 y2 y3)
  const __m256d a = _mm256_set_m128d(_mm_loadu_pd(p[2].data()), _mm_loadu_pd(p[0].data()));
  const __m256d b = _mm256_set_m128d(_mm_loadu_pd(p[3].data()), _mm_loadu_pd(p[1].data()));
  const __m256d x = _mm256_unpacklo_pd(a, b), y = _mm256_unpackhi_pd(a, b);
  const __m256d dot = _mm256_add_pd(_mm256_mul_pd(_mm256_sub_pd(x, ax), ex), _mm256_mul_pd(_mm256_sub_pd(y, ay), ey));
  const __m256d t = kExact ? _mm256_div_pd(dot, _mm256_set1_pd(k[4])) : _mm256_mul_pd(dot, inv_l2);
  const __m256d u = _mm256_min_pd(_mm256_set1_pd(1.0), _mm256_max_pd(_mm256_setzero_pd(), t));
  const __m256d cx = _mm256_sub_pd(_mm256_add_pd(ax, _mm256_mul_pd(u, ex)), x);
  const __m256d cy = _mm256_sub_pd(_mm256_add_pd(ay, _mm256_mul_pd(u, ey)), y);
  return _mm256_add_pd(_mm256_mul_pd(cx, cx), _mm256_mul_pd(cy, cy));
}
LASONIC_AVX2 inline __m256d chordSquaresAvx2(const Vec2* p, const double* k) {
  return chordSquaresAvx2<true>(p, k, _mm256_setzero_pd());
}
LASONIC_AVX2 size_t chordSquaresAvx2(const Vec2* p, size_t count, const double* k, double* out) {
  size_t i = 0;
  for (; i + 4 <= count; i += 4) _mm256_storeu_pd(out + i, chordSquaresAvx2(p + i, k));
  return i;
}
LASONIC_AVX2 size_t farthestAvx2(const Vec2* p, size_t count, const double* k, double& m2, size_t& at) {
  size_t i = 0;
  for (; i + 4 <= count; i += 4) {
    const __m256d d2 = chordSquaresAvx2(p + i, k);
    if (_mm256_movemask_pd(_mm256_cmp_pd(d2, _mm256_set1_pd(m2), _CMP_GT_OQ)) == 0) continue;
    alignas(32) double v[4];
    _mm256_store_pd(v, d2);
    for (size_t l = 0; l < 4; ++l) takeOver(v[l], i + l, m2, at);
  }
  return i;
}

// farthest() over p[0 .. count-1] in two passes, with the same choice. The first pass takes the
// approximate squares (chordSquaresAvx2<false>) and their largest, M. An approximate root differs
// from the exact one by less than E = 2^-40 (|a| + |e| + sqrt M) (max norms; the bound is about
// 2^-46 times that: the quotient is within 2^-50 of the exact one after clamping to [0, 1], and
// the steps after it round alike), so every point of the largest exact root has an approximate
// root of at least sqrt M - 2 E. The second pass takes the exact squares of only those points
// (a few), in order, as farthest() does. Returns false, having changed nothing, where the bound
// is not known to hold: a chord far outside 1e-100 .. 1e100, or a square NaN or beyond 1e200.
LASONIC_AVX2 bool screenedFarthestAvx2(const ChordDistance& chord, const Vec2* p, size_t count, const double* k,
                                       double& m2, size_t& at) {
  const double l2 = k[4];
  const double a_max = std::max(std::abs(k[0]), std::abs(k[1])), e_max = std::max(std::abs(k[2]), std::abs(k[3]));
  if (!(l2 > 1e-100 && l2 < 1e100 && a_max < 1e100)) return false;
  thread_local std::vector<double> approx;  // (scratch)
  approx.resize(count);
  const __m256d inv_l2 = _mm256_set1_pd(1.0 / l2);
  __m256d top = _mm256_setzero_pd(), odd = _mm256_setzero_pd();  // odd: a NaN lane
  size_t i = 0;
  for (; i + 4 <= count; i += 4) {
    const __m256d d2 = chordSquaresAvx2<false>(p + i, k, inv_l2);
    _mm256_storeu_pd(approx.data() + i, d2);
    top = _mm256_max_pd(top, d2);
    odd = _mm256_or_pd(odd, _mm256_cmp_pd(d2, d2, _CMP_UNORD_Q));
  }
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, top);
  double top2 = std::max(std::max(lanes[0], lanes[1]), std::max(lanes[2], lanes[3]));
  bool nan = _mm256_movemask_pd(odd) != 0;
  for (; i < count; ++i) {  // the tail: the exact square (within the bound too)
    approx[i] = chord.squared(p[i]);
    nan = nan || std::isnan(approx[i]);
    top2 = std::max(top2, approx[i]);
  }
  if (nan || !(top2 < 1e200)) return false;  // (and low * low below stays finite)
  const double root = std::sqrt(top2);
  const double bound = 0x1p-40 * (a_max + e_max + root);
  const double low = root - 4 * bound;  // (2 E with a margin)
  const double low2 = low > 0 ? low * low * (1 - 0x1p-40) : -1.0;  // at most low^2
  for (size_t j = 0; j < count; ++j)
    if (approx[j] >= low2) takeOver(chord.squared(p[j]), j, m2, at);
  return true;
}
#endif

void ChordDistance::squaredMany(const Vec2* p, size_t count, double* out) const {
  size_t i = 0;
  if (!(l2_ <= 0.0)) {
    const double k[5] = {a_.x(), a_.y(), e_.x(), e_.y(), l2_};
    const VectorPath path = vectorPath();
#if LASONIC_AVX2_LOOP
    if (path == VectorPath::Avx2) i = chordSquaresAvx2(p, count, k, out);
#endif
#if defined(__SSE2__)
    for (; path != VectorPath::Scalar && i + 2 <= count; i += 2) _mm_storeu_pd(out + i, chordSquaresSse2(p + i, k));
#endif
  }
  for (; i < count; ++i) out[i] = squared(p[i]);
}

void ChordDistance::farthest(const Vec2* p, size_t count, double& m2, size_t& at) const {
  size_t i = 0;
  if (!(l2_ <= 0.0)) {
    const double k[5] = {a_.x(), a_.y(), e_.x(), e_.y(), l2_};
    const VectorPath path = vectorPath();
#if LASONIC_AVX2_LOOP
    // (Long runs screened first: the exact loop's division is its bottleneck.)
    if (path == VectorPath::Avx2 && count >= 16 && screenedFarthestAvx2(*this, p, count, k, m2, at)) return;
    if (path == VectorPath::Avx2) i = farthestAvx2(p, count, k, m2, at);
#endif
#if defined(__SSE2__)
    for (; path != VectorPath::Scalar && i + 2 <= count; i += 2) {
      const __m128d d2 = chordSquaresSse2(p + i, k);
      if (_mm_movemask_pd(_mm_cmpgt_pd(d2, _mm_set1_pd(m2))) == 0) continue;
      takeOver(_mm_cvtsd_f64(d2), i, m2, at);
      takeOver(_mm_cvtsd_f64(_mm_unpackhi_pd(d2, d2)), i + 1, m2, at);
    }
#endif
  }
  for (; i < count; ++i) takeOver(squared(p[i]), i, m2, at);
}

void splitRecursive(const std::vector<Vec2>& pts, size_t i, size_t j, double threshold,
                    std::vector<IndexRange>& out) {
  // The first point farthest from the chord (takeOver). m2: the leader's square, -1 for none.
  double m2 = -1;
  size_t kmax = 0;  // (offset from i + 1)
  if (j > i + 1) ChordDistance(geom::Segment{pts[i], pts[j]}).farthest(pts.data() + i + 1, j - i - 1, m2, kmax);
  kmax = m2 < 0 ? i : i + 1 + kmax;
  const double dmax = m2 < 0 ? -1.0 : std::sqrt(m2);
  if (dmax < threshold) {
    out.push_back({i, j});
    return;
  }
  splitRecursive(pts, i, kmax, threshold, out);
  splitRecursive(pts, kmax, j, threshold, out);
}
}  // namespace

void chordSquaredDistances(const geom::Segment& chord, const Vec2* points, size_t count, double* out) {
  ChordDistance(chord).squaredMany(points, count, out);
}

std::vector<IndexRange> iterativeEndPointFit(const std::vector<Vec2>& points, IndexRange r,
                                             double threshold) {
  std::vector<IndexRange> out;
  if (points.empty() || r.last >= points.size() || r.first > r.last) return out;
  splitRecursive(points, r.first, r.last, threshold, out);
  return out;
}

RmSegment fitLine(const std::vector<Vec2>& points, IndexRange r) {
  const double n = static_cast<double>(r.size());
  Vec2 c = Vec2::Zero();
  for (size_t k = r.first; k <= r.last; ++k) c += points[k];
  c /= n;
  double sxx = 0, syy = 0, sxy = 0;
  for (size_t k = r.first; k <= r.last; ++k) {
    const Vec2 d = points[k] - c;
    sxx += d.x() * d.x();
    syy += d.y() * d.y();
    sxy += d.x() * d.y();
  }
  // Principal axis of the scatter: minimises the sum of squared orthogonal distances. The rms is
  // taken from the residuals below (not the minor eigenvalue): the same value up to rounding.
  const Vec2 dir = geom::unitVector(geom::principalAxes(sxx, syy, sxy).angle);
  const Vec2 nrm(-dir.y(), dir.x());
  double ss = 0;
  for (size_t k = r.first; k <= r.last; ++k) {
    const double e = (points[k] - c).dot(nrm);
    ss += e * e;
  }
  RmSegment s;
  s.seg = {c + dir * (points[r.first] - c).dot(dir), c + dir * (points[r.last] - c).dot(dir)};
  s.npoints = static_cast<int>(r.size());
  s.rms = std::sqrt(ss / n);
  return s;
}

void joinCorner(RmSegment& a, RmSegment& b, double max_shift) {
  const Vec2 da = a.seg.b - a.seg.a, db = b.seg.b - b.seg.a;
  const double denom = da.x() * db.y() - da.y() * db.x();
  // Below ~10 deg between the lines the intersection is ill-conditioned (and no real corner).
  if (std::abs(denom) < std::sin(geom::deg2rad(10.0)) * da.norm() * db.norm()) return;
  const Vec2 w = b.seg.a - a.seg.a;
  const Vec2 x = a.seg.a + da * ((w.x() * db.y() - w.y() * db.x()) / denom);
  if ((x - a.seg.b).norm() > max_shift || (x - b.seg.a).norm() > max_shift) return;
  a.seg.b = x;
  b.seg.a = x;
}

namespace {
// clusterSegments of the cluster points[first .. first + count), appended to out; returns how many.
size_t appendClusterSegments(const std::vector<Vec2>& points, size_t first, size_t count, bool closed,
                             const RadarMapConfig& cfg, std::vector<RmSegment>& out) {
  const size_t min_points = static_cast<size_t>(std::max(2, cfg.min_points));
  if (count < min_points) return 0;
  thread_local std::vector<IndexRange> ranges;  // (scratch)
  ranges.clear();
  // An open cluster is fitted in place; a closed one is first cut at a breakpoint of a first
  // pass (a corner) and closed there, in a copy.
  std::vector<Vec2> loop;
  if (closed) {
    loop.assign(points.begin() + static_cast<std::ptrdiff_t>(first),
                points.begin() + static_cast<std::ptrdiff_t>(first + count));
    splitRecursive(loop, 0, loop.size() - 1, cfg.split_threshold, ranges);
    const size_t corner = ranges.size() > 1 ? ranges.front().last : 0;
    std::rotate(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(corner), loop.end());
    loop.push_back(loop.front());
    ranges.clear();
    first = 0;
    count = loop.size();
  }
  const std::vector<Vec2>& pts = closed ? loop : points;
  splitRecursive(pts, first, first + count - 1, cfg.split_threshold, ranges);
  const size_t before = out.size();
  for (const IndexRange& r : ranges) {
    if (r.size() < min_points) continue;
    RmSegment s = fitLine(pts, r);
    if (s.seg.length() < cfg.min_length) continue;
    if (out.size() > before) joinCorner(out.back(), s, cfg.jump_abs);
    out.push_back(s);
  }
  if (closed && out.size() - before > 2) joinCorner(out.back(), out[before], cfg.jump_abs);
  return out.size() - before;
}
}  // namespace

std::vector<RmSegment> clusterSegments(const Cluster& cluster, const RadarMapConfig& cfg) {
  std::vector<RmSegment> out;
  appendClusterSegments(cluster.points, 0, cluster.points.size(), cluster.closed, cfg, out);
  return out;
}

bool LaserView::covers(const geom::Vec2& p) const {
  if (full_circle) return true;
  const geom::Vec2 d = p - sensor.position();
  // The bearing relative to the first reading, in [0, 2 pi): inside when not beyond the last one.
  double a = std::atan2(d.y(), d.x()) - sensor.theta - angle_min;
  a -= 2 * geom::kPi * std::floor(a / (2 * geom::kPi));
  return a <= angle_max - angle_min;
}

LaserView laserViewOf(const LaserScan& scan, const geom::Pose2& robot) {
  LaserView v;
  v.full_circle = scan.full_circle || scan.readings.empty();
  v.sensor = robot.compose(scan.mount);
  if (!scan.readings.empty()) {
    v.angle_min = scan.readings.front().angle;
    v.angle_max = scan.readings.back().angle;
  }
  return v;
}

LaserView laserViewOf(const LaserScan& scan, const geom::Pose2& robot, const geom::Pose2& robot_at_first) {
  LaserView v = laserViewOf(scan, robot);
  const size_t n = scan.readings.size();
  if (!scan.full_circle || n < 2) return v;
  const LaserReading& front = scan.readings.front();
  const LaserReading& back = scan.readings.back();
  const double spacing = (back.angle - front.angle) / static_cast<double>(n - 1);
  // The turn from the earliest reading to the latest; the sweep runs from the earliest reading to
  // the latest: counter-clockwise when the first by angle is the earliest.
  const double turn = geom::angleDiff(robot.theta, robot_at_first.theta);
  const bool ccw = front.utime <= back.utime;
  if (ccw && turn < -spacing) {  // the earliest reading (the first by angle) lies at front - turn
    v.full_circle = false;
    v.angle_min = front.angle - turn;
    v.angle_max = back.angle;
  } else if (!ccw && turn > spacing) {  // the earliest reading (the last by angle) lies at back - turn
    v.full_circle = false;
    v.angle_min = front.angle;
    v.angle_max = back.angle - turn;
  }
  return v;
}

DarkBearings::DarkBearings(const LaserScan& scan, const LaserView& view, const std::vector<uint8_t>& empty)
    : view_(view) {
  const size_t n = std::min(scan.readings.size(), empty.size());
  if (n < 2) return;
  step_ = (view.angle_max - view.angle_min) / static_cast<double>(n - 1);
  dark_.assign(n, 0);
  full_ = scan.full_circle;
  const bool full = full_;
  for (size_t i = 0; i < n; ++i) {
    if (!empty[i]) continue;
    const bool before = i > 0 ? empty[i - 1] != 0 : full && empty[n - 1] != 0;
    const bool after = i + 1 < n ? empty[i + 1] != 0 : full && empty[0] != 0;
    if (before && after) dark_[i] = 1, any_ = true;
  }
}

namespace {
// atan2 within 1.2e-5 rad (about a thousandth of the 0.5 deg between readings), without the
// library call: the memory asks it for each of a scan's ~700 returns.
double approxAtan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double mx = std::max(ax, ay);
  if (mx == 0) return 0;
  const double z = std::min(ax, ay) / mx, z2 = z * z;
  double a = z * (0.9998660 + z2 * (-0.3302995 + z2 * (0.1801410 + z2 * (-0.0851330 + z2 * 0.0208351))));
  if (ay > ax) a = geom::kPi / 2 - a;
  if (x < 0) a = geom::kPi - a;
  return y < 0 ? -a : a;
}
}  // namespace

bool DarkBearings::at(const geom::Vec2& p) const {
  if (!any_ || !(step_ > 0)) return false;
  const geom::Vec2 d = p - view_.sensor.position();
  double a = approxAtan2(d.y(), d.x()) - view_.sensor.theta - view_.angle_min;
  // [0, 2 pi) from the first reading (each of the three terms lies within a turn or so)
  for (int turns = 0; a < 0 && turns < 8; ++turns) a += 2 * geom::kPi;
  for (int turns = 0; a >= 2 * geom::kPi && turns < 8; ++turns) a -= 2 * geom::kPi;
  if (!(a >= 0 && a < 2 * geom::kPi)) return false;  // (NaN, or a heading beyond any sense)
  const auto n = static_cast<int64_t>(dark_.size());
  int64_t k = static_cast<int64_t>(a / step_ + 0.5);
  if (k >= n) {  // past the last reading: outside the view, or (a full circle) the first again
    if (!full_) return false;
    k -= n;
  }
  return k >= 0 && k < n && dark_[static_cast<size_t>(k)];
}

void appendScanSegments(const std::vector<ScanPoint>& points, bool full_circle, const RadarMapConfig& cfg,
                        std::vector<RmSegment>& segments, std::vector<std::vector<geom::Vec2>>* pole_candidates) {
  thread_local FlatClusters clusters;  // (scratch)
  splitClustersFlat(points, full_circle, cfg, clusters);
  for (size_t k = 0; k < clusters.size(); ++k) {
    const size_t first = clusters.first(k), count = clusters.count(k);
    if (appendClusterSegments(clusters.flat, first, count, clusters.closed, cfg, segments) == 0 && pole_candidates &&
        cfg.pole_min_points > 0 && count >= static_cast<size_t>(cfg.pole_min_points))
      pole_candidates->emplace_back(clusters.flat.begin() + static_cast<std::ptrdiff_t>(first),
                                    clusters.flat.begin() + static_cast<std::ptrdiff_t>(first + count));
  }
}

namespace {

RadarMap radarMapOf(const LaserScan& scan, const std::vector<ScanPoint>& points, std::optional<geom::Pose2> pose,
                    const RadarMapConfig& cfg) {
  RadarMap rm;
  rm.source_utime = firstReadingTime(scan);
  rm.utime = lastReadingTime(scan);
  rm.robot_pose = pose.value_or(geom::Pose2{});
  rm.view = laserViewOf(scan, rm.robot_pose);
  appendScanSegments(points, scan.full_circle, cfg, rm.segments, &rm.pole_candidates);
  rm.corners = rightAngleCorners(rm.segments);
  return rm;
}
}  // namespace

// The earliest and the latest of the readings' times: the first and the last reading of a
// counter-clockwise scanner, the last and the first of a clockwise one (its readings reversed).
int64_t firstReadingTime(const LaserScan& scan) {
  if (scan.readings.empty()) return scan.utime;
  int64_t t = scan.readings.front().utime;
  for (const LaserReading& r : scan.readings) t = std::min(t, r.utime);
  return t;
}

int64_t lastReadingTime(const LaserScan& scan) {
  if (scan.readings.empty()) return scan.utime;
  int64_t t = scan.readings.back().utime;
  for (const LaserReading& r : scan.readings) t = std::max(t, r.utime);
  return t;
}

bool RmCorner::inside(const geom::Vec2& p) const {
  const geom::Vec2 d = p - vertex;
  const auto cross = [](const geom::Vec2& a, const geom::Vec2& b) { return a.x() * b.y() - a.y() * b.x(); };
  const double turn = cross(arm_a, arm_b);  // the side of arm_a on which arm_b lies
  return cross(arm_a, d) * turn > 0 && cross(d, arm_b) * turn > 0;
}

std::vector<RmCorner> rightAngleCorners(const std::vector<RmSegment>& segments, double join, double angle_tol) {
  std::vector<RmCorner> out;
  const double max_cos = std::sin(angle_tol);  // |cos(angle)| <= sin(tol) <=> |angle - 90 deg| <= tol
  for (size_t i = 0; i < segments.size(); ++i)
    for (size_t j = i + 1; j < segments.size(); ++j) {
      const geom::Segment &s = segments[i].seg, &t = segments[j].seg;
      for (int ei = 0; ei < 2; ++ei)
        for (int ej = 0; ej < 2; ++ej) {
          const geom::Vec2& a = ei ? s.b : s.a;
          const geom::Vec2& b = ej ? t.b : t.a;
          if ((a - b).norm() > join) continue;
          const geom::Vec2 v = 0.5 * (a + b);
          const geom::Vec2 ua = (ei ? s.a : s.b) - v, ub = (ej ? t.a : t.b) - v;
          if (ua.norm() < join || ub.norm() < join) continue;
          RmCorner c{v, ua.normalized(), ub.normalized()};
          if (std::abs(c.arm_a.dot(c.arm_b)) <= max_cos) out.push_back(c);
        }
    }
  return out;
}

RadarMap extractRadarMap(const LaserScan& scan, const PoseLookup& pose_at, const RadarMapConfig& cfg,
                         int* no_pose) {
  const auto pose = pose_at(lastReadingTime(scan));
  return radarMapOf(scan, placeReadings(scan, pose_at, no_pose), pose, cfg);
}

RadarMap extractRadarMap(const LaserScan& scan, const PoseHistory& poses, const RadarMapConfig& cfg, int* no_pose) {
  const auto pose = poses.at(lastReadingTime(scan));
  thread_local std::vector<ScanPoint> placed;  // (scratch: its storage, scan after scan)
  placeReadingsInto(scan, poses, placed, no_pose);
  return radarMapOf(scan, placed, pose, cfg);
}

RadarMap radarMapFromPlaced(const LaserScan& scan, const std::vector<ScanPoint>& placed, const PoseHistory& poses,
                            const RadarMapConfig& cfg) {
  return radarMapOf(scan, placed, poses.at(lastReadingTime(scan)), cfg);
}

}  // namespace lasonic::complement
