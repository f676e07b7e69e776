#include "operational/sector_map.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include "operational/laser_shadow.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
// laserValues' AVX2 loop: compiled on x86-64 whatever the build's baseline (a function
// attribute), run only where the CPU has AVX2 (asked at run time).
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define LASONIC_AVX2_LOOP 1
#define LASONIC_AVX2 __attribute__((target("avx2")))  // not "fma": see laserValues
#else
#define LASONIC_AVX2_LOOP 0
#endif

namespace lasonic {

namespace {
bool known(float d) { return d >= 0; }

// The largest double t with std::sqrt(t) <= r (r >= 0, finite).
double sqrtBound(double r) {
  double t = r * r;
  while (std::sqrt(t) > r) t = std::nextafter(t, 0.0);
  while (std::sqrt(std::nextafter(t, std::numeric_limits<double>::infinity())) <= r)
    t = std::nextafter(t, std::numeric_limits<double>::infinity());
  return t;
}
}  // namespace

SectorMap::SectorMap(const SectorMapParams& p) : p_(p) {
  if (p.sectors < 3 || !(p.robot_radius >= 0) || !(p.max_range > 0) || p.gp_threshold < 1 ||
      !(p.copy_confirm_tolerance >= 0) || !(p.laser_explains_radius >= 0) || !(p.remembered_stale_s > 0))
    throw std::invalid_argument("SectorMap: inconsistent parameters");
  const auto n = static_cast<size_t>(p.sectors);
  laser_now_.resize(n);
  laser_r2_.resize(n);
  const double reach = p.robot_radius + p.max_range;
  reach_root_bound_ = std::isfinite(reach) ? sqrtBound(reach) : reach;
  sonar_own_.resize(n);
  sonar_reach_.resize(n);
  sonar_copyable_.resize(n);
  sonar_now_.resize(n);
  held_laser_.resize(n);
  held_sonar_.resize(n);
  remembered_now_.resize(n);
  s_.distance.assign(n, -1);
  s_.remembered.assign(n, -1);
  s_.laser.assign(n, -1);
  s_.sonar.assign(n, -1);
  s_.source.assign(n, SectorSource::None);
  for (size_t k = 0; k <= n; ++k) {
    const double a = -geom::kPi + static_cast<double>(k) * (2.0 * geom::kPi / static_cast<double>(n));
    bound_c_.push_back(std::cos(a));
    bound_s_.push_back(std::sin(a));
  }
}

namespace {
SectorMap::VectorPath widestPath() {
#if LASONIC_AVX2_LOOP
  __builtin_cpu_init();  // (in case this runs before the constructors)
  // (AVX2 only where the OS also saves the 256-bit registers.)
  if (__builtin_cpu_supports("avx2")) return SectorMap::VectorPath::Avx2;
#endif
#if defined(__SSE2__)
  return SectorMap::VectorPath::Sse2;
#else
  return SectorMap::VectorPath::Scalar;
#endif
}

std::atomic<SectorMap::VectorPath>& pathInUse() {
  static std::atomic<SectorMap::VectorPath> path{widestPath()};  // the CPU asked once
  return path;
}
}  // namespace

void SectorMap::setVectorPath(VectorPath widest) {
  pathInUse().store(std::min(widest, widestPath()), std::memory_order_relaxed);
}

SectorMap::VectorPath SectorMap::vectorPath() { return pathInUse().load(std::memory_order_relaxed); }

namespace {
// atan2 to within about 1e-5 rad (a candidate only: sectorOfDirection checks it).
inline double roughAtan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double mx = std::max(ax, ay), mn = std::min(ax, ay);
  if (!(mx > 0)) return 0;
  const double a = mn / mx, s = a * a;
  double r = ((-0.0464964749 * s + 0.15931422) * s - 0.327622764) * s * a + a;
  if (ay > ax) r = 1.57079632679489662 - r;
  if (x < 0) r = 3.14159265358979324 - r;
  return y < 0 ? -r : r;
}
}  // namespace

// Exactness: the sector computed from atan2 differs from the geometric sector (the wedge between
// two edge directions) only for directions within a few ulp of an edge. A candidate from a rough
// atan2 is accepted when the direction lies inside its wedge by a relative margin of 1e-9 (both
// edge cross products, which for a wedge under 180 deg define it); anything else -- near an
// edge, the +-pi seam, zero, NaN -- takes the exact path.
bool SectorMap::clearlyInside(int k, double x, double y) const {
  const double margin = 1e-9 * (std::abs(x) + std::abs(y));
  const auto kk = static_cast<size_t>(k);
  return bound_c_[kk] * y - bound_s_[kk] * x > margin && x * bound_s_[kk + 1] - y * bound_c_[kk + 1] > margin;
}

template <typename Exact>
int SectorMap::sectorOfDirection(double x, double y, Exact&& exact) const {
  const int n = p_.sectors;
  int k = static_cast<int>(std::floor((roughAtan2(y, x) + geom::kPi) * (n / (2.0 * geom::kPi))));
  if (k >= 0 && k < n && clearlyInside(k, x, y)) return k;
  return exact();
}

int SectorMap::sectorOf(double bearing) const { return sectorOfNormalized(geom::normalizeAngle(bearing)); }

int SectorMap::sectorOfNormalized(double bearing) const {
  const int k = static_cast<int>(std::floor((bearing + geom::kPi) * (p_.sectors / (2.0 * geom::kPi))));
  return k >= p_.sectors ? k - p_.sectors : std::max(k, 0);  // bearing pi is -pi: sector 0
}

void SectorMap::setLaserMovers(std::vector<MovingPoint> movers, double horizon_s) {
  laser_movers_ = std::move(movers);
  movers_horizon_s_ = std::isfinite(horizon_s) ? std::max(0.0, horizon_s) : 0.0;
}

std::vector<geom::Vec2> SectorMap::setLaserPoints(int64_t utime, std::vector<geom::Vec2> points) {
  laser_movers_.clear();
  scan_returns_.clear();
  scan_valid_.clear();
  laser_shadow_.clear();
  shadow_made_ = false;
  std::swap(laser_points_, points);
  points.clear();
  laser_x_.resize(laser_points_.size());
  laser_y_.resize(laser_points_.size());
  for (size_t i = 0; i < laser_points_.size(); ++i) {
    laser_x_[i] = laser_points_[i].x();
    laser_y_[i] = laser_points_[i].y();
  }
  laser_utime_ = utime;
  have_laser_ = true;
  explained_cell_size_ = 0;  // rebuilt for the AGM's cell size at the next update
  laser_bucket_size_ = 0;
  return points;
}

void SectorMap::setLaserScan(std::vector<geom::Vec2>& returns, std::vector<uint8_t>& valid, const geom::Vec2& origin,
                             bool full_circle) {
  std::swap(scan_returns_, returns);
  std::swap(scan_valid_, valid);
  scan_origin_ = origin;
  scan_full_circle_ = full_circle;
  laser_shadow_.clear();
  shadow_made_ = false;
}

void SectorMap::rebuildLaserBuckets(double rho) {
  laser_buckets_.clear();
  laser_bucket_size_ = rho;
  for (const auto& p : laser_points_)
    laser_buckets_.push_back({{static_cast<int64_t>(std::clamp(std::floor(p.x() / rho), -1e15, 1e15)),
                               static_cast<int64_t>(std::clamp(std::floor(p.y() / rho), -1e15, 1e15))},
                              p});
  std::sort(laser_buckets_.begin(), laser_buckets_.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
}

bool SectorMap::laserNear(const geom::Vec2& p, double rho) const {
  if (!(rho > 0) || laser_buckets_.empty()) return false;
  const int64_t bx = static_cast<int64_t>(std::clamp(std::floor(p.x() / rho), -1e15, 1e15));
  const int64_t by = static_cast<int64_t>(std::clamp(std::floor(p.y() / rho), -1e15, 1e15));
  for (int64_t x = bx - 1; x <= bx + 1; ++x)
    for (int64_t y = by - 1; y <= by + 1; ++y) {
      const std::pair<int64_t, int64_t> key{x, y};
      auto it = std::lower_bound(laser_buckets_.begin(), laser_buckets_.end(), key,
                                 [](const auto& e, const auto& k) { return e.first < k; });
      for (; it != laser_buckets_.end() && it->first == key; ++it)
        if ((it->second - p).norm() <= rho) return true;
    }
  return false;
}

// cellIndices, four at a time where the CPU has AVX2 (SectorMap::vectorPath), else two at a time
// where SSE2 is there: the quotient by the same division; floor(clamp(t)) = clamp(floor(t)) as
// +-1e15 are integers; floor of |t| <= 1e15 < 2^51 exact by rounding to an integer at 1.5 * 2^52
// and stepping down where that rounded up. (The same operations lane by lane in both widths.)
namespace {
int64_t cellIndexOf(double x, double cell) {
  return static_cast<int64_t>(std::clamp(std::floor(x / cell), -1e15, 1e15));
}
#if LASONIC_AVX2_LOOP
// Four at a time, first without the division: q' = v * (1 / cell) is within 2^-51 |q| of the
// quotient q = v / cell (both rounded), so where no integer lies within 2^-40 max(1, |q'|) of q'
// (then |q'| < 2^39, well inside the clamp) none lies between q' and q, and floor(q') = floor(q).
// Four such lanes are floored and converted in the vector (an integer f, |f| < 2^51, is the low
// bits of f + 1.5 * 2^52); otherwise the four go the defining way below: a cell edge within a
// few ulp, NaN, huge values, or a cell outside 1e-150 .. 1e150 (where 1 / cell may lose bits).
LASONIC_AVX2 size_t cellIndicesAvx2(const double* v, size_t n, double cell, int64_t* out) {
  const __m256d c = _mm256_set1_pd(cell), lo = _mm256_set1_pd(-1e15), hi = _mm256_set1_pd(1e15);
  const __m256d big = _mm256_set1_pd(6755399441055744.0), unit = _mm256_set1_pd(1.0);
  const bool screen = cell > 1e-150 && cell < 1e150;
  const __m256d inv = _mm256_set1_pd(screen ? 1.0 / cell : 0.0), band = _mm256_set1_pd(0x1p-40);
  const __m256d sign = _mm256_set1_pd(-0.0);
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d x = _mm256_loadu_pd(v + i);
    if (screen) {
      const __m256d q = _mm256_mul_pd(x, inv);
      const __m256d r = _mm256_sub_pd(_mm256_add_pd(q, big), big);  // q rounded to an integer (|q| < 2^51)
      const __m256d off = _mm256_andnot_pd(sign, _mm256_sub_pd(q, r));
      const __m256d room = _mm256_mul_pd(_mm256_max_pd(_mm256_andnot_pd(sign, q), unit), band);
      if (_mm256_movemask_pd(_mm256_cmp_pd(off, room, _CMP_GT_OQ)) == 15) {  // (NaN: not greater)
        const __m256d f = _mm256_sub_pd(r, _mm256_and_pd(_mm256_cmp_pd(r, q, _CMP_GT_OS), unit));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + i),
                            _mm256_sub_epi64(_mm256_castpd_si256(_mm256_add_pd(f, big)), _mm256_castpd_si256(big)));
        continue;
      }
    }
    const __m256d q = _mm256_div_pd(x, c);
    // A NaN quotient goes the scalar way (the vector min and max would not keep it).
    if (_mm256_movemask_pd(_mm256_cmp_pd(q, q, _CMP_UNORD_Q)) != 0) {
      for (size_t j = i; j < i + 4; ++j) out[j] = cellIndexOf(v[j], cell);
      continue;
    }
    const __m256d t = _mm256_min_pd(_mm256_max_pd(q, lo), hi);
    const __m256d r = _mm256_sub_pd(_mm256_add_pd(t, big), big);
    const __m256d f = _mm256_sub_pd(r, _mm256_and_pd(_mm256_cmp_pd(r, t, _CMP_GT_OS), unit));  // (_mm_cmpgt_pd's)
    const __m128d f0 = _mm256_castpd256_pd128(f), f1 = _mm256_extractf128_pd(f, 1);
    out[i] = _mm_cvttsd_si64(f0);
    out[i + 1] = _mm_cvttsd_si64(_mm_unpackhi_pd(f0, f0));
    out[i + 2] = _mm_cvttsd_si64(f1);
    out[i + 3] = _mm_cvttsd_si64(_mm_unpackhi_pd(f1, f1));
  }
  return i;
}
#endif
}  // namespace

void cellIndices(const double* v, size_t n, double cell, int64_t* out) {
  size_t i = 0;
  const SectorMap::VectorPath path = SectorMap::vectorPath();
#if LASONIC_AVX2_LOOP
  if (path == SectorMap::VectorPath::Avx2) i = cellIndicesAvx2(v, n, cell, out);
#endif
#if defined(__SSE2__)
  const __m128d c = _mm_set1_pd(cell), lo = _mm_set1_pd(-1e15), hi = _mm_set1_pd(1e15);
  const __m128d big = _mm_set1_pd(6755399441055744.0), unit = _mm_set1_pd(1.0);
  for (; path != SectorMap::VectorPath::Scalar && i + 2 <= n; i += 2) {
    const __m128d q = _mm_div_pd(_mm_loadu_pd(v + i), c);
    // A NaN quotient goes the scalar way (the vector min and max would not keep it).
    if (_mm_movemask_pd(_mm_cmpunord_pd(q, q)) != 0) {
      out[i] = cellIndexOf(v[i], cell);
      out[i + 1] = cellIndexOf(v[i + 1], cell);
      continue;
    }
    const __m128d t = _mm_min_pd(_mm_max_pd(q, lo), hi);
    const __m128d r = _mm_sub_pd(_mm_add_pd(t, big), big);
    const __m128d f = _mm_sub_pd(r, _mm_and_pd(_mm_cmpgt_pd(r, t), unit));
    out[i] = _mm_cvttsd_si64(f);
    out[i + 1] = _mm_cvttsd_si64(_mm_unpackhi_pd(f, f));
  }
#endif
  for (; i < n; ++i) out[i] = cellIndexOf(v[i], cell);
}

namespace {
// The smallest and largest of v[0 .. n-1] (n >= 1).
#if LASONIC_AVX2_LOOP
LASONIC_AVX2 void minMaxAvx2(const int64_t* v, size_t n, int64_t& lo, int64_t& hi) {
  size_t i = 0;
  if (n >= 4) {
    // Two running extremes each (eight values a round), so that a round does not wait for the last.
    __m256i l = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v)), h = l, l2 = l, h2 = l;
    const auto take = [](__m256i& lo4, __m256i& hi4, __m256i x) LASONIC_AVX2 {
      lo4 = _mm256_blendv_epi8(lo4, x, _mm256_cmpgt_epi64(lo4, x));
      hi4 = _mm256_blendv_epi8(hi4, x, _mm256_cmpgt_epi64(x, hi4));
    };
    for (i = 4; i + 8 <= n; i += 8) {
      take(l, h, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + i)));
      take(l2, h2, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + i + 4)));
    }
    if (i + 4 <= n) take(l, h, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + i))), i += 4;
    alignas(32) int64_t ls[4], hs[4], ls2[4], hs2[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(ls), l);
    _mm256_store_si256(reinterpret_cast<__m256i*>(hs), h);
    _mm256_store_si256(reinterpret_cast<__m256i*>(ls2), l2);
    _mm256_store_si256(reinterpret_cast<__m256i*>(hs2), h2);
    for (size_t k = 0; k < 4; ++k)
      lo = std::min({lo, ls[k], ls2[k]}), hi = std::max({hi, hs[k], hs2[k]});
  }
  for (; i < n; ++i) lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
}

// out[i] = ((gy[i] - y0) >> shift) * w + ((gx[i] - x0) >> shift) as uint32, four at a time, for
// differences in [0, 2^31) and w < 2^31 (the bucket box); returns how many it did.
LASONIC_AVX2 size_t bucketIdsAvx2(const int64_t* gx, const int64_t* gy, size_t n, int64_t x0, int64_t y0,
                                  int shift, int64_t w, uint32_t* out) {
  const __m256i vx0 = _mm256_set1_epi64x(x0), vy0 = _mm256_set1_epi64x(y0), vw = _mm256_set1_epi64x(w);
  const __m128i sh = _mm_cvtsi32_si128(shift);
  const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256i bx = _mm256_srl_epi64(_mm256_sub_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(gx + i)), vx0), sh);
    const __m256i by = _mm256_srl_epi64(_mm256_sub_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(gy + i)), vy0), sh);
    const __m256i b = _mm256_add_epi64(_mm256_mul_epu32(by, vw), bx);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i),
                     _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(b, low_halves)));
  }
  return i;
}
#endif
void minMax(const int64_t* v, size_t n, int64_t& lo, int64_t& hi) {
#if LASONIC_AVX2_LOOP
  if (SectorMap::vectorPath() == SectorMap::VectorPath::Avx2) return minMaxAvx2(v, n, lo, hi);
#endif
  for (size_t i = 0; i < n; ++i) lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
}
}  // namespace

// The explained cells: cell (x, y) is explained when a point p of the newest scan has
// (x, y) in its candidate box (within +-span cells of p's own cell, narrowed to the cells whose
// centres can lie within rho, with one cell of margin against rounding) and the centre of
// (x, y) lies within rho of p. A map asks about a few dozen cells (the AGM's cells at Gp >=
// gp_threshold, the remembered points near the robot), so each cell is decided when first asked
// and remembered until the next scan, from the points bucketed by cell once per scan: a few
// microseconds per scan instead of marking every cell around each of the scan's points.
int64_t SectorMap::explainedGlobal(double v) const {
  return static_cast<int64_t>(std::clamp(std::floor(v / explained_cell_size_), -1e15, 1e15));
}

bool SectorMap::explainedBy(int64_t x, int64_t y, const geom::Vec2& p) const {
  const double c = explained_cell_size_, rho = p_.laser_explains_radius;
  const int64_t gx = explainedGlobal(p.x()), gy = explainedGlobal(p.y());
  const int64_t sp = explained_span_;
  const auto first = [c, rho](double v, int64_t g, int64_t span) {
    return std::max(g - span, static_cast<int64_t>(std::clamp(std::floor((v - rho) / c - 0.5), -1e15, 1e15)));
  };
  const auto last = [c, rho](double v, int64_t g, int64_t span) {
    return std::min(g + span, static_cast<int64_t>(std::clamp(std::floor((v + rho) / c - 0.5), -1e15, 1e15)) + 1);
  };
  if (x < first(p.x(), gx, sp) || x > last(p.x(), gx, sp) || y < first(p.y(), gy, sp) || y > last(p.y(), gy, sp))
    return false;
  return withinRho(x, y, p);
}

bool SectorMap::withinRho(int64_t x, int64_t y, const geom::Vec2& p) const {
  const double c = explained_cell_size_;
  return (geom::Vec2((static_cast<double>(x) + 0.5) * c, (static_cast<double>(y) + 0.5) * c) - p).squaredNorm() <=
         explained_rho2_;
}

void SectorMap::rebuildExplained(double c) {
  // Once per scan (not per map).
  explained_.clear();
  explained_known_.clear();
  explained_bits_.clear();
  bucket_start_.clear();
  bucket_runs_.clear();
  explained_w_ = explained_h_ = 0;
  explained_any_ = false;
  explained_cell_size_ = c;
  const double rho = p_.laser_explains_radius;
  if (!(rho > 0) || laser_points_.empty()) return;
  const int64_t span = static_cast<int64_t>(std::ceil(rho / c)) + 1;
  explained_span_ = span;
  // norm() <= rho without the square root: sqrt is correctly rounded, hence monotonic, so
  // sqrt(d2) <= rho exactly when d2 <= the largest double whose root is <= rho.
  explained_rho2_ = sqrtBound(rho);
  int64_t x0 = std::numeric_limits<int64_t>::max(), y0 = x0, x1 = std::numeric_limits<int64_t>::min(), y1 = x1;
  point_gx_.resize(laser_points_.size());
  point_gy_.resize(laser_points_.size());
  cellIndices(laser_x_.data(), laser_points_.size(), c, point_gx_.data());  // explainedGlobal of each
  cellIndices(laser_y_.data(), laser_points_.size(), c, point_gy_.data());
  // (Each point's candidate box is its cell +- span: the box of all is the cells' extremes +- span.)
  minMax(point_gx_.data(), point_gx_.size(), x0, x1);
  minMax(point_gy_.data(), point_gy_.size(), y0, y1);
  x0 -= span, x1 += span, y0 -= span, y1 += span;
  constexpr int64_t kMaxBits = int64_t{1} << 26;  // 8 MB: a 400 m square at 5 cm
  const bool box_ok = x1 - x0 < (int64_t{1} << 31) && y1 - y0 < (int64_t{1} << 31) &&
                      (x1 - x0 + 1) <= kMaxBits / (y1 - y0 + 1);
  if (box_ok) {
    explained_x0_ = x0;
    explained_y0_ = y0;
    explained_w_ = x1 - x0 + 1;
    explained_h_ = y1 - y0 + 1;
    const auto words = static_cast<size_t>((explained_w_ * explained_h_ + 63) / 64);
    explained_known_.assign(words, 0);
    explained_bits_.assign(words, 0);
    // Square buckets of at least 2 span + 1 cells over the box (counting sort): the points that
    // can explain a cell lie in at most 2 x 2 of them.
    bucket_shift_ = 0;  // a power of two >= 2 span + 1 cells: shifts, not divisions
    while ((int64_t{1} << bucket_shift_) < 2 * span + 1) ++bucket_shift_;
    const int64_t side = int64_t{1} << bucket_shift_;
    bucket_w_ = (explained_w_ + side - 1) / side;
    const int64_t bucket_h = (explained_h_ + side - 1) / side;
    const auto buckets = static_cast<size_t>(bucket_w_ * bucket_h);
    bucket_start_.assign(buckets + 1, 0);
    const size_t np = laser_points_.size();
    point_bucket_.resize(np);
    // (Through local pointers: a store through a member vector could, as far as the compiler
    // knows, change the vector itself.)
    const int64_t* gxs = point_gx_.data();
    const int64_t* gys = point_gy_.data();
    uint32_t* pb = point_bucket_.data();
    const int64_t shift = bucket_shift_, w = bucket_w_;
    size_t i0 = 0;
#if LASONIC_AVX2_LOOP
    if (vectorPath() == VectorPath::Avx2) i0 = bucketIdsAvx2(gxs, gys, np, x0, y0, static_cast<int>(shift), w, pb);
#endif
    for (size_t i = i0; i < np; ++i)
      pb[i] = static_cast<uint32_t>(((gys[i] - y0) >> shift) * w + ((gxs[i] - x0) >> shift));
    // The runs of consecutive points in one bucket (a scan's neighbours mostly share one), put
    // in bucket order by a counting sort: a cell is decided from the runs of the buckets around
    // it, each a stretch of laser_points_ (sorting runs, not points: a few times fewer).
    run_first_.resize(np + 1);
    uint32_t* first = run_first_.data();
    uint32_t* count = bucket_start_.data() + 1;
    size_t runs = 0;
    for (size_t i = 0; i < np;) {
      const uint32_t b = pb[i];
      first[runs++] = static_cast<uint32_t>(i);
      ++count[b];
      do ++i;
      while (i < np && pb[i] == b);
    }
    first[runs] = static_cast<uint32_t>(np);
    for (size_t b = 1; b <= buckets; ++b) bucket_start_[b] += bucket_start_[b - 1];
    bucket_fill_.assign(bucket_start_.begin(), bucket_start_.end() - 1);
    uint32_t* fill = bucket_fill_.data();
    bucket_runs_.resize(runs);
    std::pair<uint32_t, uint32_t>* dst = bucket_runs_.data();
    for (size_t r = 0; r < runs; ++r) dst[fill[pb[first[r]]]++] = {first[r], first[r + 1]};
    explained_any_ = true;  // (not known yet; every cell is decided when asked)
    return;
  }
  for (const auto& p : laser_points_) {
    const int64_t gx = explainedGlobal(p.x()), gy = explainedGlobal(p.y());
    for (int64_t y = gy - span; y <= gy + span; ++y)
      for (int64_t x = gx - span; x <= gx + span; ++x)
        if (withinRho(x, y, p)) explained_.emplace_back(x, y);
  }
  std::sort(explained_.begin(), explained_.end());
  explained_.erase(std::unique(explained_.begin(), explained_.end()), explained_.end());
  explained_any_ = !explained_.empty();
}

bool SectorMap::explainedCell(int64_t gx, int64_t gy) const {
  if (explained_w_ > 0) {
    if (gx < explained_x0_ || gy < explained_y0_ || gx - explained_x0_ >= explained_w_ || gy - explained_y0_ >= explained_h_)
      return false;
    const auto bit = static_cast<size_t>((gy - explained_y0_) * explained_w_ + (gx - explained_x0_));
    const uint64_t mask = uint64_t{1} << (bit & 63);
    if (explained_known_[bit >> 6] & mask) return (explained_bits_[bit >> 6] & mask) != 0;
    // (>> of a negative difference rounds down: clamped to bucket 0.)
    const int64_t bx0 = std::max<int64_t>(0, (gx - explained_span_ - explained_x0_) >> bucket_shift_);
    const int64_t bx1 = std::min<int64_t>(bucket_w_ - 1, (gx + explained_span_ - explained_x0_) >> bucket_shift_);
    const int64_t bucket_h = static_cast<int64_t>(bucket_start_.size() - 1) / bucket_w_;
    const int64_t by0 = std::max<int64_t>(0, (gy - explained_span_ - explained_y0_) >> bucket_shift_);
    const int64_t by1 = std::min<int64_t>(bucket_h - 1, (gy + explained_span_ - explained_y0_) >> bucket_shift_);
    bool found = false;
    for (int64_t by = by0; by <= by1 && !found; ++by)
      for (int64_t bx = bx0; bx <= bx1 && !found; ++bx) {
        const auto b = static_cast<size_t>(by * bucket_w_ + bx);
        for (uint32_t r = bucket_start_[b]; r < bucket_start_[b + 1] && !found; ++r)
          for (uint32_t i = bucket_runs_[r].first; i < bucket_runs_[r].second && !found; ++i)
            found = explainedBy(gx, gy, laser_points_[i]);
      }
    explained_known_[bit >> 6] |= mask;
    if (found) explained_bits_[bit >> 6] |= mask;
    return found;
  }
  return std::binary_search(explained_.begin(), explained_.end(), std::make_pair(gx, gy));
}

void SectorMap::setSonarTime(int64_t utime) {
  sonar_utime_ = utime;
  have_sonar_ = true;
}

void SectorMap::setRemembered(int64_t utime, std::vector<geom::Vec2> points) {
  remembered_points_ = std::move(points);
  remembered_utime_ = utime;
  have_remembered_ = true;
}

bool SectorMap::explained(const geom::Vec2& p) const {
  if (!explained_any_ || !(explained_cell_size_ > 0)) return false;
  return explainedCell(explainedGlobal(p.x()), explainedGlobal(p.y()));
}

void SectorMap::rememberedValues(const geom::Pose2& pose, double ct, double st, std::vector<Value>& out,
                                 bool check_laser) const {
  std::fill(out.begin(), out.end(), Value{});
  // r <= robot_radius + max_range exactly when r^2 <= reach2 (sqrt is correctly rounded).
  const double reach2 = reach_root_bound_;
  // The bearing's sector by rotation, as for the AGM's cells (sonarValues).
  const bool plain_theta = std::abs(pose.theta) <= 4 * geom::kPi;
  // Each sector keeps the smallest distance of the points it holds that the laser does not
  // explain (the float of the smallest double, whatever the order), so a point that would not
  // lower its sector's value is passed over before asking whether the laser explains it: that
  // question (a cell look-up) is the expensive part, and most points within the reach lie
  // behind a nearer one of the same obstacle. Neighbouring cells mostly share a sector: the
  // previous point's is tried first (clearly inside it is inside it, whatever proposed it).
  int hint = 0;
  for (const geom::Vec2& p : remembered_points_) {
    const geom::Vec2 d = p - pose.position();
    const double r2 = d.squaredNorm();
    if (!(r2 <= reach2)) continue;  // the root only for the few points within reach
    const double r = std::sqrt(r2);
    const double dist = std::max(0.0, r - p_.robot_radius);
    if (dist > p_.max_range) continue;
    const auto exact = [&] { return sectorOf(std::atan2(d.y(), d.x()) - pose.theta); };
    int k;
    if (plain_theta) {
      const double x = ct * d.x() + st * d.y(), y = ct * d.y() - st * d.x();
      k = clearlyInside(hint, x, y) ? hint : sectorOfDirection(x, y, exact);
    } else {
      k = exact();
    }
    hint = k;
    Value& v = out[static_cast<size_t>(k)];
    if (known(v.d) && !(dist < v.d)) continue;
    // The laser reports it, at its own bearing (a stale scan explains nothing away).
    if (check_laser &&
        (p_.remembered_explains_radius > 0 ? laserNear(p, p_.remembered_explains_radius) : explained(p)))
      continue;
    v = {static_cast<float>(dist), SectorSource::Remembered};
  }
}

void SectorMap::laserValues(const geom::Pose2& pose, double c, double s, bool shadow, std::vector<Value>& out) const {
  std::fill(out.begin(), out.end(), Value{});
  // "Moved into the current pose": global -> robot frame (Pose2::inverseTransform, with the
  // rotation c = cos(theta), s = sin(theta) computed once per map instead of once per point).
  const double reach = p_.robot_radius + p_.max_range;
  const double reach2 = reach * reach;
  // Per sector the smallest squared distance; the root only once per sector at the end: the
  // distance max(0, sqrt(r2) - robot_radius), rounded to float, never decreases with r2, so the
  // minimum over the points is the distance of the smallest r2 (and the order in which the
  // points are taken does not matter).
  std::fill(laser_r2_.begin(), laser_r2_.end(), -1.0);  // -1: no point
  const int n = p_.sectors;
  int k = 0;
  const auto exact = [&](double lx, double ly) {
    return sectorOfDirection(lx, ly, [&] { return sectorOfNormalized(std::atan2(ly, lx)); });
  };
  const auto take = [&](int sector, double r2) {
    double& m = laser_r2_[static_cast<size_t>(sector)];
    if (m < 0 || r2 < m) m = r2;
  };
  // One point (dx, dy: from the robot, global frame), the defining computation.
  const auto one = [&](double dx, double dy) __attribute__((noinline)) {  // (out of the four-lane loop's registers)
    const double r2 = dx * dx + dy * dy;
    if (r2 > reach2) return;
    const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
    if (std::isnan(r2)) {  // (not from a valid scan) distance max(0, NaN) = 0, as for r2 = 0
      laser_r2_[static_cast<size_t>(exact(lx, ly))] = 0.0;
      return;
    }
    // The scan's points come in bearing order, so most lie in the previous point's sector or
    // the next one; a direction clearly inside a sector is in that sector whatever candidate
    // proposed it.
    if (!clearlyInside(k, lx, ly)) {
      const int up = k + 1 == n ? 0 : k + 1, down = k == 0 ? n - 1 : k - 1;
      k = clearlyInside(up, lx, ly) ? up : clearlyInside(down, lx, ly) ? down : exact(lx, ly);
    }
    take(k, r2);
  };
  const double* xs = laser_x_.data();
  const double* ys = laser_y_.data();
  const size_t np = laser_x_.size();
  size_t i = 0;
  // (An infinite reach: one() only.)
  const VectorPath path = std::isfinite(reach2) ? vectorPath() : VectorPath::Scalar;
#if LASONIC_AVX2_LOOP
  // The SSE2 loop below in 256-bit registers, one per quantity instead of two: the same lanes,
  // operations and operand order, hence the same values; the next sector tried before the
  // fallback. Compiled for AVX2 but not FMA: a fused a * b + c is rounded once and would change
  // the values. (Index and count as locals: through references, as far as the compiler knows,
  // one() could change them, and they would be stored and reloaded each time round.)
  const auto four_avx2 = [&, np](size_t at) LASONIC_AVX2 {
    const __m256d vc = _mm256_set1_pd(c), vs = _mm256_set1_pd(s), vms = _mm256_set1_pd(-s);
    const __m256d vpx = _mm256_set1_pd(pose.x), vpy = _mm256_set1_pd(pose.y), vreach2 = _mm256_set1_pd(reach2);
    const __m256d vinf = _mm256_set1_pd(std::numeric_limits<double>::infinity());
    const __m256d margin = _mm256_set1_pd(2e-9 * reach);  // (see the SSE2 loop)
    const __m256i lane_bit = _mm256_set_epi64x(8, 4, 2, 1);
    __m256d bc, bs, bc1, bs1;  // sector k's edges
    const auto edges = [&]() LASONIC_AVX2 {
      const auto kk = static_cast<size_t>(k);
      bc = _mm256_set1_pd(bound_c_[kk]), bs = _mm256_set1_pd(bound_s_[kk]);
      bc1 = _mm256_set1_pd(bound_c_[kk + 1]), bs1 = _mm256_set1_pd(bound_s_[kk + 1]);
    };
    edges();
    __m256d acc = vinf;  // the smallest r^2 so far of the lanes clearly inside sector k
    const auto flush = [&]() LASONIC_AVX2 {
      const __m128d m2 = _mm_min_pd(_mm256_castpd256_pd128(acc), _mm256_extractf128_pd(acc, 1));
      const double m = _mm_cvtsd_f64(_mm_min_sd(m2, _mm_unpackhi_pd(m2, m2)));
      if (m <= reach2) take(k, m);
      acc = vinf;
    };
    for (; at + 4 <= np; at += 4) {
      const __m256d dx = _mm256_sub_pd(_mm256_loadu_pd(xs + at), vpx), dy = _mm256_sub_pd(_mm256_loadu_pd(ys + at), vpy);
      const __m256d r2 = _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy));
      const int todo = _mm256_movemask_pd(_mm256_cmp_pd(r2, vreach2, _CMP_NGT_US));  // (_mm_cmpngt_pd's)
      if (todo == 0) continue;
      const __m256d lx = _mm256_add_pd(_mm256_mul_pd(vc, dx), _mm256_mul_pd(vs, dy));
      const __m256d ly = _mm256_add_pd(_mm256_mul_pd(vms, dx), _mm256_mul_pd(vc, dy));
      const auto inside = [&]() LASONIC_AVX2 {
        return _mm256_movemask_pd(_mm256_cmp_pd(_mm256_min_pd(_mm256_sub_pd(_mm256_mul_pd(bc, ly), _mm256_mul_pd(bs, lx)),
                                                              _mm256_sub_pd(_mm256_mul_pd(lx, bs1), _mm256_mul_pd(ly, bc1))),
                                                margin, _CMP_GT_OS));  // (_mm_cmpgt_pd's)
      };
      int rest = todo & ~inside();
      if (rest == 0) {
        acc = _mm256_min_pd(acc, r2);
        continue;
      }
      const auto accumulate = [&](int bits) LASONIC_AVX2 {
        const __m256i sel = _mm256_and_si256(_mm256_set1_epi64x(bits), lane_bit);
        acc = _mm256_min_pd(acc, _mm256_blendv_pd(vinf, r2, _mm256_castsi256_pd(_mm256_cmpeq_epi64(sel, lane_bit))));
      };
      accumulate(todo & ~rest);
      flush();
      // A lane outside k: nearly always in the next sector (the scan's points come in bearing
      // order), tried first in the registers, not through one() as below. A lane clearly inside
      // a sector lies in it whichever sector k was, so the order of the tries changes no value.
      k = k + 1 == n ? 0 : k + 1;
      edges();
      const int next = rest & inside();
      accumulate(next);
      rest &= ~next;
      if (rest == 0) continue;
      flush();
      const int last = 31 - __builtin_clz(static_cast<unsigned>(rest));
      one(xs[at + static_cast<size_t>(last)] - pose.x, ys[at + static_cast<size_t>(last)] - pose.y);
      rest &= ~(1 << last);
      edges();
      if (rest == 0) continue;
      const int again = rest & inside();
      accumulate(again);
      rest &= ~again;
      if (rest == 0) continue;
      flush();
      for (size_t j = 0; j < 4; ++j)
        if (rest & (1 << j)) one(xs[at + j] - pose.x, ys[at + j] - pose.y);
      edges();
    }
    flush();
    return at;
  };
  if (path == VectorPath::Avx2) i = four_avx2(i);
#endif
#if defined(__SSE2__)
  // Four points at a time (two SSE2 registers of two; SSE2 is part of x86-64's baseline):
  // distance, rotation and clearlyInside(k) for all four at once, each lane by the same
  // operations as one() (no FMA on this target), hence with the same values. When every lane is
  // beyond the reach or clearly inside the current sector k (nearly always), the lanes inside go
  // into a running minimum for k (r^2 < reach2 < infinity: infinity means none); otherwise the
  // lanes not beyond the reach go through one() in turn.
  if (path == VectorPath::Sse2) {
    const __m128d vc = _mm_set1_pd(c), vs = _mm_set1_pd(s), vms = _mm_set1_pd(-s);
    const __m128d vpx = _mm_set1_pd(pose.x), vpy = _mm_set1_pd(pose.y), vreach2 = _mm_set1_pd(reach2);
    const __m128d vinf = _mm_set1_pd(std::numeric_limits<double>::infinity());
    // One margin for all lanes, at least clearlyInside's 1e-9 (|x| + |y|) for any lane within the
    // reach (|x| + |y| <= sqrt(2) r <= 1.5 reach): inside by more is inside.
    const __m128d m0 = _mm_set1_pd(2e-9 * reach), m1 = m0;
    __m128d bc, bs, bc1, bs1;  // sector k's edges
    const auto edges = [&] {
      const auto kk = static_cast<size_t>(k);
      bc = _mm_set1_pd(bound_c_[kk]), bs = _mm_set1_pd(bound_s_[kk]);
      bc1 = _mm_set1_pd(bound_c_[kk + 1]), bs1 = _mm_set1_pd(bound_s_[kk + 1]);
    };
    edges();
    __m128d acc = vinf;  // the smallest r^2 so far of the lanes clearly inside sector k
    const auto flush = [&] {
      const double m = _mm_cvtsd_f64(_mm_min_sd(acc, _mm_unpackhi_pd(acc, acc)));
      if (m <= reach2) take(k, m);
      acc = vinf;
    };
    for (; i + 4 <= np; i += 4) {
      const __m128d dx0 = _mm_sub_pd(_mm_loadu_pd(xs + i), vpx), dx1 = _mm_sub_pd(_mm_loadu_pd(xs + i + 2), vpx);
      const __m128d dy0 = _mm_sub_pd(_mm_loadu_pd(ys + i), vpy), dy1 = _mm_sub_pd(_mm_loadu_pd(ys + i + 2), vpy);
      const __m128d r20 = _mm_add_pd(_mm_mul_pd(dx0, dx0), _mm_mul_pd(dy0, dy0));
      const __m128d r21 = _mm_add_pd(_mm_mul_pd(dx1, dx1), _mm_mul_pd(dy1, dy1));
      // Within the reach, or NaN (one() skips exactly the lanes with r2 > reach2).
      const __m128d ok0 = _mm_cmpngt_pd(r20, vreach2), ok1 = _mm_cmpngt_pd(r21, vreach2);
      const int todo = _mm_movemask_pd(ok0) | (_mm_movemask_pd(ok1) << 2);
      if (todo == 0) continue;
      const __m128d lx0 = _mm_add_pd(_mm_mul_pd(vc, dx0), _mm_mul_pd(vs, dy0));
      const __m128d lx1 = _mm_add_pd(_mm_mul_pd(vc, dx1), _mm_mul_pd(vs, dy1));
      const __m128d ly0 = _mm_add_pd(_mm_mul_pd(vms, dx0), _mm_mul_pd(vc, dy0));
      const __m128d ly1 = _mm_add_pd(_mm_mul_pd(vms, dx1), _mm_mul_pd(vc, dy1));
      // clearlyInside(k), lane by lane (never true for a NaN direction; the smaller of the two
      // edge cross products above the margin).
      const auto inside = [&](__m128d& in0, __m128d& in1) {
        in0 = _mm_cmpgt_pd(_mm_min_pd(_mm_sub_pd(_mm_mul_pd(bc, ly0), _mm_mul_pd(bs, lx0)),
                                      _mm_sub_pd(_mm_mul_pd(lx0, bs1), _mm_mul_pd(ly0, bc1))), m0);
        in1 = _mm_cmpgt_pd(_mm_min_pd(_mm_sub_pd(_mm_mul_pd(bc, ly1), _mm_mul_pd(bs, lx1)),
                                      _mm_sub_pd(_mm_mul_pd(lx1, bs1), _mm_mul_pd(ly1, bc1))), m1);
        return _mm_movemask_pd(in0) | (_mm_movemask_pd(in1) << 2);
      };
      __m128d in0, in1;
      int rest = todo & ~inside(in0, in1);
      if (rest == 0) {
        // Every lane within the reach is inside k: the others have r^2 > reach2, above all of
        // those, so the plain minimum of the four is that of the lanes inside when it is <= reach2.
        acc = _mm_min_pd(acc, _mm_min_pd(r20, r21));
        continue;
      }
      // The lanes in `bits` (inside k) into the running minimum.
      const auto accumulate = [&](int bits) {
        const auto lane = [bits](int b) { return -static_cast<long long>(bits >> b & 1); };  // all ones or 0
        const __m128d h0 = _mm_castsi128_pd(_mm_set_epi64x(lane(1), lane(0)));
        const __m128d h1 = _mm_castsi128_pd(_mm_set_epi64x(lane(3), lane(2)));
        acc = _mm_min_pd(acc, _mm_min_pd(_mm_or_pd(_mm_and_pd(h0, r20), _mm_andnot_pd(h0, vinf)),
                                         _mm_or_pd(_mm_and_pd(h1, r21), _mm_andnot_pd(h1, vinf))));
      };
      accumulate(todo & ~rest);
      // A lane outside k (the next sector, nearly always; or NaN): the last such lane through
      // one(), which finds its sector and moves k there; the others tried against the new k,
      // and what is left through one() as well.
      flush();
      const int last = 31 - __builtin_clz(static_cast<unsigned>(rest));
      one(xs[i + static_cast<size_t>(last)] - pose.x, ys[i + static_cast<size_t>(last)] - pose.y);
      rest &= ~(1 << last);
      edges();
      if (rest == 0) continue;
      const int again = rest & inside(in0, in1);
      accumulate(again);
      rest &= ~again;
      if (rest == 0) continue;
      flush();
      for (size_t j = 0; j < 4; ++j)
        if (rest & (1 << j)) one(xs[i + j] - pose.x, ys[i + j] - pose.y);
      edges();
    }
    flush();
  }
#endif
  for (; i < np; ++i) one(xs[i] - pose.x, ys[i] - pose.y);
  // Moving returns where they are now (extrapolated from their own time, at most the horizon).
  for (const MovingPoint& mp : laser_movers_) {
    const double age = std::clamp(static_cast<double>(s_.utime - mp.utime) * 1e-6, 0.0, movers_horizon_s_);
    const geom::Vec2 q = mp.p + age * mp.v;
    const double dx = q.x() - pose.x, dy = q.y() - pose.y;
    const double r2 = dx * dx + dy * dy;
    if (!(r2 <= reach2)) continue;  // (also NaN: a mover is never put at the robot)
    take(exact(c * dx + s * dy, -s * dx + c * dy), r2);
  }
  // The last scan's shadow edges, only while it is stale (StaleValues::Frontier): fresh, the next
  // scan looks into them within a scan period.
  if (shadow)
    for (const geom::Vec2& q : laser_shadow_) {
      const double dx = q.x() - pose.x, dy = q.y() - pose.y;
      const double r2 = dx * dx + dy * dy;
      if (!(r2 <= reach2)) continue;
      take(exact(c * dx + s * dy, -s * dx + c * dy), r2);
    }
  for (size_t j = 0; j < out.size(); ++j)
    if (laser_r2_[j] >= 0)
      out[j] = {static_cast<float>(std::max(0.0, std::sqrt(laser_r2_[j]) - p_.robot_radius)), SectorSource::Laser};
}

template <typename Grid>
void SectorMap::sonarValues(const geom::Pose2& pose, double ct, double st, const Grid& agm, bool use_explained,
                            std::vector<Value>& out, std::vector<Value>& spread, std::vector<Value>& copyable) const {
  std::fill(out.begin(), out.end(), Value{});
  std::fill(spread.begin(), spread.end(), Value{});
  const bool copy_held = p_.copy_held;
  if (!copy_held) std::fill(copyable.begin(), copyable.end(), Value{});
  const bool extent = p_.copy_rule == CopyRule::CellExtent;
  const int n = p_.sectors;
  const bool check = use_explained && explained_any_;
  const int64_t ox = agm.originX(), oy = agm.originY();
  const double c = agm.cellSize();
  const double reach = p_.robot_radius + p_.max_range;
  const geom::Vec2 o = agm.originMetres();
  const geom::Vec2 robot = pose.position();
  const auto cell = [&](double v, double origin) { return static_cast<int>(std::floor((v - origin) / c)); };
  // The cell's bearing in the robot frame by rotation (sectorOfDirection); for a heading far
  // outside [-4pi, 4pi], atan2 - theta has lost the precision that argument needs: exact path.
  const bool plain_theta = std::abs(pose.theta) <= 4 * geom::kPi;
  // Only cells with weight can reach gp_threshold (>= 1). Their order does not matter: each
  // sector keeps the minimum, and all values of one kind carry the same source.
  agm.forEachWeightedCell(cell(robot.x() - reach, o.x()), cell(robot.y() - reach, o.y()), cell(robot.x() + reach, o.x()),
                  cell(robot.y() + reach, o.y()), [&](int ix, int iy, int, int gp) {
                    if (gp < p_.gp_threshold) return;
                    if (check && explainedCell(ox + ix, oy + iy)) return;
                    const geom::Vec2 lo = o + geom::Vec2(ix * c, iy * c);
                    const geom::Vec2 centre = lo + geom::Vec2(0.5 * c, 0.5 * c) - robot;
                    const geom::Vec2 nearest(std::clamp(robot.x(), lo.x(), lo.x() + c),
                                             std::clamp(robot.y(), lo.y(), lo.y() + c));
                    const double r =
                        p_.sonar_cell_point == CellPoint::Centre ? centre.norm() : (nearest - robot).norm();
                    const double d = std::max(0.0, r - p_.robot_radius);
                    if (d > p_.max_range) return;
                    const auto exact = [&] { return sectorOf(std::atan2(centre.y(), centre.x()) - pose.theta); };
                    const int k0 = plain_theta ? sectorOfDirection(ct * centre.x() + st * centre.y(),
                                                                   ct * centre.y() - st * centre.x(), exact)
                                               : exact();
                    Value& v = out[static_cast<size_t>(k0)];
                    if (!known(v.d) || d < v.d) v = {static_cast<float>(d), SectorSource::Sonar};
                    if (!copy_held && !agm.held(ix, iy)) {
                      Value& w = copyable[static_cast<size_t>(k0)];
                      if (!known(w.d) || d < w.d) w = {static_cast<float>(d), SectorSource::Sonar};
                    }
                    if (!extent) return;
                    const double bearing = std::atan2(centre.y(), centre.x()) - pose.theta;  // k0 is its sector
                    // CellExtent: the obstacle is somewhere in the cell's square, so also in every
                    // other sector the square reaches (its half-diagonal seen from the robot).
                    const double half = std::asin(std::min(1.0, (c * 0.7071067811865476) / std::max(centre.norm(), c)));
                    const int k_lo = sectorOf(bearing - half), k_hi = sectorOf(bearing + half);
                    for (int k = k_lo;; k = (k + 1) % n) {
                      if (k != k0) {
                        Value& r2 = spread[static_cast<size_t>(k)];
                        if (!known(r2.d) || d < r2.d) r2 = {static_cast<float>(d), SectorSource::SonarCopied};
                      }
                      if (k == k_hi) break;
                    }
                  });
}

void SectorMap::hold(bool stale, std::vector<Value>& now, std::vector<Value>& held) const {
  if (stale && p_.stale_values == StaleValues::HeldMin) {
    for (size_t k = 0; k < now.size(); ++k)
      if (known(held[k].d) && (!known(now[k].d) || held[k].d < now[k].d)) now[k] = held[k];
  }
  held = now;
}

const SectorMapState& SectorMap::update(int64_t utime, const geom::Pose2& pose, const AccumulativeGridMap& agm) {
  return updateWith(utime, pose, agm);
}

const SectorMapState& SectorMap::update(int64_t utime, const geom::Pose2& pose, const OccupancyWindow& grid) {
  if (grid.size < 0 || grid.occupied.size() != static_cast<size_t>(grid.size) * static_cast<size_t>(grid.size) ||
      !(grid.cell_size > 0))
    throw std::invalid_argument("SectorMap: OccupancyWindow of inconsistent size");
  return updateWith(utime, pose, grid);
}

template <typename Grid>
const SectorMapState& SectorMap::updateWith(int64_t utime, const geom::Pose2& pose, const Grid& agm) {
  const size_t n = static_cast<size_t>(p_.sectors);
  s_.utime = utime;
  s_.pose = pose;
  s_.laser_age_s = have_laser_ ? static_cast<double>(utime - laser_utime_) * 1e-6 : -1.0;
  s_.sonar_age_s = have_sonar_ ? static_cast<double>(utime - sonar_utime_) * 1e-6 : -1.0;
  s_.laser_stale = !have_laser_ || s_.laser_age_s > p_.laser_stale_s;
  s_.sonar_stale = !have_sonar_ || s_.sonar_age_s > p_.sonar_stale_s;
  s_.remembered_age_s = have_remembered_ ? static_cast<double>(utime - remembered_utime_) * 1e-6 : -1.0;
  s_.remembered_stale = !have_remembered_ || s_.remembered_age_s > p_.remembered_stale_s;

  // The rotation into the robot frame, once for the three parts.
  const double ct = std::cos(pose.theta), st = std::sin(pose.theta);
  const bool shadow = s_.laser_stale && p_.stale_values == StaleValues::Frontier;
  if (shadow && !shadow_made_) {  // once per scan, and only for the scan that became the last one
    LaserShadowParams sp;
    sp.reach = 2 * (p_.robot_radius + p_.max_range);
    laserShadow(scan_returns_, scan_valid_, scan_origin_, scan_full_circle_, sp, laser_shadow_);
    shadow_made_ = true;
  }
  laserValues(pose, ct, st, shadow, laser_now_);
  if (explained_cell_size_ != agm.cellSize()) rebuildExplained(agm.cellSize());
  // A stale scan no longer says what is where: it explains nothing away.
  sonarValues(pose, ct, st, agm, !s_.laser_stale, sonar_own_, sonar_reach_, sonar_copyable_);
  // Copy rule: own sonar values spread into both neighbours that hold no sonar data of their own
  // (with CopyRule::UnlessLaserConfirmed, not from a sector whose laser value confirms it).
  const bool skip_confirmed = p_.copy_rule == CopyRule::UnlessLaserConfirmed;
  for (size_t k = 0; k < n; ++k) {
    sonar_now_[k] = sonar_own_[k];
    if (known(sonar_own_[k].d) && !p_.copy_over_own) continue;
    if (p_.copy_rule == CopyRule::CellExtent) {
      const Value& r = sonar_reach_[k];
      if (known(r.d) && (!known(sonar_now_[k].d) || r.d < sonar_now_[k].d)) sonar_now_[k] = r;
      continue;
    }
    for (const size_t j : {k == 0 ? n - 1 : k - 1, k + 1 == n ? 0 : k + 1}) {  // (no division per sector)
      const float d = (p_.copy_held ? sonar_own_ : sonar_copyable_)[j].d;
      if (skip_confirmed && known(d) && known(laser_now_[j].d) &&
          std::abs(laser_now_[j].d - d) <= p_.copy_confirm_tolerance)
        continue;
      if (known(d) && (!known(sonar_now_[k].d) || d < sonar_now_[k].d))
        sonar_now_[k] = {d, SectorSource::SonarCopied};
    }
  }
  hold(s_.laser_stale, laser_now_, held_laser_);
  hold(s_.sonar_stale, sonar_now_, held_sonar_);
  // Memory is not held: stale (or never received), it is simply not used.
  if (s_.remembered_stale) std::fill(remembered_now_.begin(), remembered_now_.end(), Value{});
  else {
    if (p_.remembered_explains_radius > 0 && laser_bucket_size_ != p_.remembered_explains_radius)
      rebuildLaserBuckets(p_.remembered_explains_radius);
    rememberedValues(pose, ct, st, remembered_now_, !s_.laser_stale);
  }

  for (size_t k = 0; k < n; ++k) {
    const Value& l = laser_now_[k];
    const Value& s = sonar_now_[k];
    const Value& m = remembered_now_[k];
    const Value* best = (known(l.d) && (!known(s.d) || l.d <= s.d)) ? &l : &s;
    if (known(m.d) && (!known(best->d) || m.d < best->d)) best = &m;
    s_.distance[k] = best->d;
    s_.source[k] = best->src;
    s_.laser[k] = l.d;
    s_.sonar[k] = s.d;
    s_.remembered[k] = m.d;
  }
  return s_;
}

}  // namespace lasonic
