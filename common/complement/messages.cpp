#include "complement/messages.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <limits>

#include "core/pose_msg.hpp"

// laserScanFromMessage's AVX2 loop: compiled on x86-64 whatever the build's baseline (a
// function attribute), run only where the CPU has AVX2 (complement::vectorPath()).
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define LASONIC_AVX2_LOOP 1
#define LASONIC_AVX2 __attribute__((target("avx2")))
#else
#define LASONIC_AVX2_LOOP 0
#endif

namespace lasonic::complement {
namespace {

#if LASONIC_AVX2_LOOP
static_assert(laser_scan_t::FLAG_OK == 0, "four flags compared as one zero word");
static_assert(sizeof(LaserReading) == 32 && offsetof(LaserReading, utime) == 0 && offsetof(LaserReading, angle) == 8 &&
                  offsetof(LaserReading, range) == 16 && offsetof(LaserReading, valid) == 24,
              "a reading written as one row of four 64-bit words");
// Readings i .. i + 3 where all four are the common case (offset >= 0, FLAG_OK, 0 <= range <=
// range_max, compared as floats): the scalar loop's values (utime + offset, angle_min + i *
// angle_increment, the range as a double, range >= range_min), each reading one row of the
// transposed registers (valid as the word 1 or 0: the bool and zero padding). Otherwise false,
// nothing written.
LASONIC_AVX2 bool fourReadingsAvx2(size_t i, int64_t utime, double angle_min, double angle_increment, float range_min,
                                   float range_max, const int32_t* offset_us, const int8_t* flags, const float* ranges,
                                   LaserReading* out) {
  int32_t four_flags;
  std::memcpy(&four_flags, flags + i, 4);
  if (four_flags != 0) return false;
  const __m128i off = _mm_loadu_si128(reinterpret_cast<const __m128i*>(offset_us + i));
  if (_mm_movemask_ps(_mm_castsi128_ps(off)) != 0) return false;  // a negative offset
  if (_mm_movemask_epi8(_mm_cmpgt_epi32(off, _mm_set1_epi32(input_limits::kMaxLaserOffsetUs))) != 0) return false;
  const __m128 r = _mm_loadu_ps(ranges + i);
  const __m128 ok = _mm_and_ps(_mm_cmpge_ps(r, _mm_setzero_ps()), _mm_cmple_ps(r, _mm_set1_ps(range_max)));
  if (_mm_movemask_ps(ok) != 15) return false;  // (NaN fails both)
  const __m256d u = _mm256_castsi256_pd(_mm256_add_epi64(_mm256_set1_epi64x(utime), _mm256_cvtepi32_epi64(off)));
  const auto at = [i](size_t k) { return static_cast<double>(static_cast<int64_t>(i + k)); };
  const __m256d a = _mm256_add_pd(_mm256_set1_pd(angle_min),
                                  _mm256_mul_pd(_mm256_set_pd(at(3), at(2), at(1), at(0)), _mm256_set1_pd(angle_increment)));
  const __m256d rd = _mm256_cvtps_pd(r);
  const __m128i valid = _mm_srli_epi32(_mm_castps_si128(_mm_cmpge_ps(r, _mm_set1_ps(range_min))), 31);  // 1 or 0
  const __m256d v = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(valid));
  const __m256d t0 = _mm256_unpacklo_pd(u, a), t1 = _mm256_unpackhi_pd(u, a);   // (u0 a0 u2 a2), (u1 a1 u3 a3)
  const __m256d t2 = _mm256_unpacklo_pd(rd, v), t3 = _mm256_unpackhi_pd(rd, v);  // (r0 v0 r2 v2), (r1 v1 r3 v3)
  double* o = reinterpret_cast<double*>(out + i);
  _mm256_storeu_pd(o, _mm256_permute2f128_pd(t0, t2, 0x20));
  _mm256_storeu_pd(o + 4, _mm256_permute2f128_pd(t1, t3, 0x20));
  _mm256_storeu_pd(o + 8, _mm256_permute2f128_pd(t0, t2, 0x31));
  _mm256_storeu_pd(o + 12, _mm256_permute2f128_pd(t1, t3, 0x31));
  return true;
}
#endif

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

std::string field(const char* channel, const char* name, size_t i) {
  return std::string(channel) + "." + name + "[" + std::to_string(i) + "]";
}

using input_limits::kMaxCoordinate;
using input_limits::kMaxLaserRange;
using input_limits::kMaxSonarRange;
using input_limits::kMinSonarRange;

bool plausiblePose(const pose2d_t& p) {
  return finitePose(p) && std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate;
}

}  // namespace

std::optional<OdometryInput> odometryFromMessage(const odometry_t& m, std::vector<InputProblem>& problems) {
  const std::pair<const char*, double> fields[] = {{"pose.x", m.pose.x}, {"pose.y", m.pose.y},
                                                   {"pose.theta", m.pose.theta}, {"v", m.v}, {"omega", m.omega}};
  for (const auto& [name, value] : fields) {
    if (!std::isfinite(value)) {
      problems.push_back({"rejected.odometry_nan", std::string("ODOMETRY.") + name + " = " + num(value) +
                                                       " (utime " + std::to_string(m.utime) + "): dropped"});
      return std::nullopt;
    }
  }
  if (!plausiblePose(m.pose)) {
    problems.push_back({"rejected.odometry_nan", "ODOMETRY.pose = (" + num(m.pose.x) + ", " + num(m.pose.y) +
                                                     ") is farther than " + num(kMaxCoordinate) + " m (utime " +
                                                     std::to_string(m.utime) + "): dropped"});
    return std::nullopt;
  }
  return OdometryInput{m.utime, toPose(m.pose), m.v, m.omega};
}

std::vector<ComplementInput> complementFromMessage(const complement_t& m, std::vector<InputProblem>& problems) {
  std::vector<ComplementInput> out;
  out.reserve(m.readings.size());
  auto field_name = [](size_t i, const char* f) {
    return "SONAR_COMPLEMENT.readings[" + std::to_string(i) + "]." + f;
  };
  for (size_t i = 0; i < m.readings.size(); ++i) {
    const complement_reading_t& r = m.readings[i];
    if (r.cls < complement_reading_t::CLASS_COMPLEMENTARY || r.cls > complement_reading_t::CLASS_SEEN_BEFORE) {
      problems.push_back({"rejected.complement_class",
                          field_name(i, "cls") + " = " + std::to_string(r.cls) + " (unknown class): skipped"});
      continue;
    }
    ComplementInput c;
    c.sensor_id = r.sensor_id;
    c.cls = static_cast<SonarClass>(r.cls);
    if (c.cls == SonarClass::Complementary || c.cls == SonarClass::OutsideView || c.cls == SonarClass::SeenBefore) {
      const std::pair<const char*, double> fields[] = {{"range", r.range}, {"end_x", r.end_x}, {"end_y", r.end_y}};
      bool ok = true;
      for (const auto& [name, value] : fields) {
        if (ok && !std::isfinite(value)) {
          problems.push_back({"rejected.complement_nan", field_name(i, name) + " = " + num(value) + ": skipped"});
          ok = false;
        }
      }
      if (ok && (std::abs(r.end_x) > kMaxCoordinate || std::abs(r.end_y) > kMaxCoordinate)) {
        problems.push_back({"rejected.complement_range", field_name(i, "end") + " = (" + num(r.end_x) + ", " +
                                                             num(r.end_y) + ") is farther than " + num(kMaxCoordinate) +
                                                             " m: skipped"});
        ok = false;
      }
      // A negative or absurd "echo" would also shift every neighbour's bearing.
      if (ok && (r.range < 0 || r.range > kMaxSonarRange)) {
        problems.push_back({"rejected.complement_range", field_name(i, "range") + " = " + num(r.range) +
                                                             " (not in [0, " + num(kMaxSonarRange) + "] m): skipped"});
        ok = false;
      }
      c.usable = ok;
      c.range = r.range;
      if (geom::plausibleBeamWidth(r.beam_width)) {
        c.beam_width = r.beam_width;
      } else if (ok) {
        problems.push_back({"rejected.complement_beam", field_name(i, "beam_width") + " = " + num(r.beam_width) +
                                                            " (not in (0, pi) rad): the configured beam used"});
      }
      c.end = geom::Vec2(r.end_x, r.end_y);
      // An outside-view echo's hypothesis: the newest lines' (the pilot tells an explained one).
      c.hypothetical_range = std::isfinite(r.hypothetical_range) ? r.hypothetical_range
                                                                 : std::numeric_limits<double>::quiet_NaN();
      if (plausiblePose(r.sensor_pose)) c.sensor_pose = toPose(r.sensor_pose);
      out.push_back(c);
      continue;
    }
    // A reading used only as sound that passed what lies nearer (tactical/pass_through.hpp): its
    // range so far checked (ok), then its pose; usable with its range, hypothesis, pose and beam.
    const auto asSounding = [&](bool ok, double range) {
      if (ok && !plausiblePose(r.sensor_pose)) {
        problems.push_back({"rejected.complement_pose", field_name(i, "sensor_pose") + " is not finite (or beyond " +
                                                            num(kMaxCoordinate) + " m): not used"});
        ok = false;
      }
      c.usable = ok;
      if (!ok) return;
      c.range = range;
      c.hypothetical_range = r.hypothetical_range;
      c.sensor_pose = toPose(r.sensor_pose);
      if (geom::plausibleBeamWidth(r.beam_width)) c.beam_width = r.beam_width;
    };
    if (c.cls == SonarClass::Redundant || c.cls == SonarClass::False) {
      // Heard at or beyond the laser's surface: used only as sound that passed what lies nearer.
      const std::pair<const char*, double> fields[] = {{"range", r.range}, {"hypothetical_range", r.hypothetical_range}};
      bool ok = true;
      for (const auto& [name, value] : fields) {
        if (ok && !(std::isfinite(value) && value >= 0 && value <= kMaxSonarRange)) {
          problems.push_back({"rejected.complement_range", field_name(i, name) + " = " + num(value) + " (not in [0, " +
                                                                   num(kMaxSonarRange) + "] m): not used"});
          ok = false;
        }
      }
      asSounding(ok, r.range);
    } else if (c.cls == SonarClass::Unverifiable && m.radar_map_stale == 0) {
      // Nothing answered within the hypothesis' range limit (an echo beyond it, or none): used
      // only as sound that passed what lies nearer than the hypothesis. A stale Radar Map's
      // readings are unverifiable for want of a hypothesis: not used.
      c.echo = std::isfinite(r.end_x) && std::isfinite(r.end_y);
      const double limit = std::isfinite(m.range_limit) && m.range_limit > 0 ? m.range_limit : kMaxSonarRange;
      bool ok = true;
      if (!(std::isfinite(r.hypothetical_range) && r.hypothetical_range >= 0 && r.hypothetical_range <= limit + 1e-3)) {
        problems.push_back({"rejected.complement_range", field_name(i, "hypothetical_range") + " = " +
                                                             num(r.hypothetical_range) + " (not in [0, " + num(limit) +
                                                             "] m, the range limit): not used"});
        ok = false;
      }
      if (ok && c.echo && !(std::isfinite(r.range) && r.range >= 0 && r.range <= kMaxSonarRange)) {
        problems.push_back({"rejected.complement_range", field_name(i, "range") + " = " + num(r.range) + " (not in [0, " +
                                                             num(kMaxSonarRange) + "] m): not used"});
        ok = false;
      }
      asSounding(ok, c.echo ? static_cast<double>(r.range) : static_cast<double>(r.hypothetical_range));
    } else if (c.cls == SonarClass::Unverifiable) {
      // No recent Radar Map: nothing verified, but the echo is what the sonar heard (the pilot
      // may take it while the laser is lost). A malformed one is only not taken.
      c.echo = std::isfinite(r.end_x) && std::isfinite(r.end_y);
      const double limit = std::isfinite(m.range_limit) && m.range_limit > 0 ? m.range_limit : 0.0;
      if (c.echo && std::isfinite(r.range) && r.range >= 0 && r.range <= limit &&
          std::abs(r.end_x) <= kMaxCoordinate && std::abs(r.end_y) <= kMaxCoordinate && plausiblePose(r.sensor_pose)) {
        c.unverified_echo = true;
        c.range = r.range;
        c.end = geom::Vec2(r.end_x, r.end_y);
        c.sensor_pose = toPose(r.sensor_pose);
        if (geom::plausibleBeamWidth(r.beam_width)) c.beam_width = r.beam_width;
      }
    }
    out.push_back(c);
  }
  return out;
}

std::optional<LaserScan> laserScanFromMessage(const laser_scan_t& m, std::vector<InputProblem>& problems) {
  LaserScan s;
  if (!laserScanFromMessageInto(m, problems, s)) return std::nullopt;
  return s;
}

const std::optional<LaserScan>& laserScanFromMessageInto(const laser_scan_t& m, std::vector<InputProblem>& problems,
                                                         std::optional<LaserScan>& slot) {
  if (!slot) slot.emplace();
  if (!laserScanFromMessageInto(m, problems, *slot)) slot.reset();
  return slot;
}

void counterClockwiseCopy(const laser_scan_t& m, laser_scan_t& out) {
  out = m;
  const size_t n = m.ranges.size();
  if (!(m.angle_increment < 0) || m.flags.size() != n || m.offset_us.size() != n) return;
  std::reverse(out.ranges.begin(), out.ranges.end());
  std::reverse(out.flags.begin(), out.flags.end());
  std::reverse(out.offset_us.begin(), out.offset_us.end());
  if (n > 0) out.angle_min = m.angle_min + static_cast<double>(n - 1) * m.angle_increment;
  out.angle_increment = -m.angle_increment;
}

namespace {
// `m` in counter-clockwise order; `source` the message as it came (the same one unless it was
// clockwise), whose values and reading indices the problems name.
bool scanFromCounterClockwise(const laser_scan_t& m, const laser_scan_t& source, std::vector<InputProblem>& problems,
                              LaserScan& s);
}  // namespace

bool laserScanFromMessageInto(const laser_scan_t& m, std::vector<InputProblem>& problems, LaserScan& s) {
  // A clockwise scanner (angle_increment < 0: one mounted upside down, or turning that way) is
  // read from its last reading to its first, so every consumer sees its readings in
  // counter-clockwise order, each with its own time (README "Channels").
  if (std::isfinite(m.angle_increment) && m.angle_increment < 0) {
    thread_local laser_scan_t ccw;  // (scratch, its storage reused scan to scan)
    counterClockwiseCopy(m, ccw);
    return scanFromCounterClockwise(ccw, m, problems, s);
  }
  return scanFromCounterClockwise(m, m, problems, s);
}

namespace {
bool scanFromCounterClockwise(const laser_scan_t& m, const laser_scan_t& source, std::vector<InputProblem>& problems,
                              LaserScan& s) {
  const auto n = static_cast<size_t>(std::max(0, m.nranges));
  // The index the sender gave reading i (reversed for a clockwise scan).
  const bool reversed = &m != &source;
  const auto sent = [&](size_t i) { return reversed ? n - 1 - i : i; };
  if (m.ranges.size() != n || m.flags.size() != n || m.offset_us.size() != n) {
    problems.push_back({"rejected.laser_scan", "LASER_SCAN: nranges = " + std::to_string(m.nranges) +
                                                   " but ranges/flags/offset_us hold " +
                                                   std::to_string(m.ranges.size()) + "/" +
                                                   std::to_string(m.flags.size()) + "/" +
                                                   std::to_string(m.offset_us.size())});
    return false;
  }
  if (!(std::isfinite(m.angle_increment) && m.angle_increment > 0) || !std::isfinite(m.angle_min)) {
    problems.push_back({"rejected.laser_scan", "LASER_SCAN.angle_increment = " + num(source.angle_increment) +
                                                   ", angle_min = " + num(source.angle_min) +
                                                   ": need a finite angle_min and a finite angle_increment != 0"});
    return false;
  }
  if (!plausiblePose(m.mount)) {
    problems.push_back({"rejected.laser_scan", "LASER_SCAN.mount is not finite (or beyond " + num(kMaxCoordinate) + " m)"});
    return false;
  }
  // A scan without readings says nothing; accepted, it would read as "everything is free"
  // (an empty Radar Map makes every sonar echo complementary; the pilot's laser sectors clear).
  if (n == 0) {
    problems.push_back({"rejected.laser_scan", "LASER_SCAN.nranges = 0: a scan without readings"});
    return false;
  }
  // Every reading is checked against range_max: a NaN or infinite one would accept any range.
  if (!(std::isfinite(m.range_min) && std::isfinite(m.range_max) && m.range_min >= 0 &&
        m.range_min < m.range_max && m.range_max <= kMaxLaserRange)) {
    problems.push_back({"rejected.laser_scan", "LASER_SCAN.range_min = " + num(m.range_min) + ", range_max = " +
                                                   num(m.range_max) + ": need 0 <= range_min < range_max <= " +
                                                   num(kMaxLaserRange) + " m"});
    return false;
  }
  // The readings span at most one turn (a finite but huge increment overflowed the angles to
  // infinity, and the Radar Map's points to NaN: found by fuzzing).
  if (static_cast<double>(n - 1) * m.angle_increment > 2.0 * geom::kPi + 1e-6 ||
      std::abs(m.angle_min) > 4.0 * geom::kPi || std::abs(source.angle_min) > 4.0 * geom::kPi) {
    problems.push_back({"rejected.laser_scan", "LASER_SCAN.angle_min = " + num(source.angle_min) +
                                                   ", angle_increment = " + num(source.angle_increment) + " with " +
                                                   std::to_string(n) +
                                                   " readings: more than one turn, or angle_min beyond +-4 pi"});
    return false;
  }
  s.utime = m.utime;
  s.mount = toPose(m.mount);
  s.full_circle = static_cast<double>(n) * m.angle_increment >= 2.0 * geom::kPi - 1.5 * m.angle_increment;
  s.readings.resize(n);  // (every reading is written below: what an earlier scan left does not matter)
  // The arrays through local pointers: a problem appended below cannot make the compiler
  // reload them (or the scalars) per reading.
  const int64_t utime = m.utime;
  const double angle_min = m.angle_min, angle_increment = m.angle_increment;
  const float range_min = m.range_min, range_max = m.range_max;
  const int32_t* offset_us = m.offset_us.data();
  const int8_t* flags = m.flags.data();
  const float* ranges = m.ranges.data();
  LaserReading* readings = s.readings.data();
#if LASONIC_AVX2_LOOP
  const bool avx2 = vectorPath() == VectorPath::Avx2;
#endif
  for (size_t i = 0; i < n; ++i) {
#if LASONIC_AVX2_LOOP
    // Four at a time from each multiple of four where all four are the common case.
    if (avx2 && (i & 3) == 0 && i + 4 <= n &&
        fourReadingsAvx2(i, utime, angle_min, angle_increment, range_min, range_max, offset_us, flags, ranges, readings)) {
      i += 3;
      continue;
    }
#endif
    LaserReading& r = readings[i];
    r.utime = utime + offset_us[i];
    r.angle = angle_min + static_cast<double>(static_cast<int64_t>(i)) * angle_increment;  // (the same double: i < 2^31)
    r.range = ranges[i];
    r.valid = false;
    // The common case first: a return within [range_min, range_max] (or below range_min).
    if (offset_us[i] >= 0 && offset_us[i] <= input_limits::kMaxLaserOffsetUs && flags[i] == laser_scan_t::FLAG_OK &&
        ranges[i] >= 0 && ranges[i] <= range_max) {
      r.valid = ranges[i] >= range_min;
      continue;
    }
    if (!input_limits::offsetInSweep(m.offset_us[i])) {
      problems.push_back({"rejected.laser_offset", field("LASER_SCAN", "offset_us", sent(i)) + " = " +
                                                       std::to_string(m.offset_us[i]) + " (must be in [0, " +
                                                       std::to_string(input_limits::kMaxLaserOffsetUs) + "])"});
      // Its time is unknown: the scan's own, so that it moves neither the scan's earliest nor its
      // latest reading time (firstReadingTime, lastReadingTime, the pilot's newest return),
      // wherever it lies in the scan.
      r.utime = utime;
      continue;
    }
    if (m.flags[i] == laser_scan_t::FLAG_NO_RETURN) continue;
    if (m.flags[i] != laser_scan_t::FLAG_OK) {
      problems.push_back({"rejected.laser_flag", field("LASER_SCAN", "flags", sent(i)) + " = " +
                                                     std::to_string(m.flags[i]) + " (unknown flag)"});
      continue;
    }
    const double rr = m.ranges[i];
    if (!std::isfinite(rr) || rr < 0 || rr > m.range_max) {
      problems.push_back({"rejected.laser_range", field("LASER_SCAN", "ranges", sent(i)) + " = " + num(rr) +
                                                      " (range_max " + num(m.range_max) + ")"});
      continue;
    }
    r.valid = rr >= m.range_min;  // below range_min: not a valid return (the sensor's own blind zone)
  }
  return true;
}
}  // namespace

SonarGroup sonarGroupFromMessage(const sonar_ring_t& m, std::vector<InputProblem>& problems) {
  SonarGroup g;
  g.utime = m.utime;
  g.group = m.group;
  const size_t n = m.sensor_id.size();
  if (m.range.size() != n || m.no_echo.size() != n || m.mount.size() != n) {
    problems.push_back({"rejected.sonar_ring", "SONAR_RING: sensor_id/range/no_echo/mount lengths differ (" +
                                                   std::to_string(n) + "/" + std::to_string(m.range.size()) +
                                                   "/" + std::to_string(m.no_echo.size()) + "/" +
                                                   std::to_string(m.mount.size()) + ")"});
    return g;
  }
  const double range_max = std::isfinite(m.range_max) && m.range_max > 0
                               ? std::min<double>(m.range_max, kMaxSonarRange)
                               : kMaxSonarRange;
  g.readings.reserve(n);  // (one allocation per group, not one per doubling)
  for (size_t i = 0; i < n; ++i) {
    SonarReading r;
    r.sensor_id = m.sensor_id[i];
    r.range = m.range[i];
    r.no_echo = m.no_echo[i] != 0;
    r.mount = {m.mount[i].x, m.mount[i].y, m.mount[i].theta};
    if (i < m.beam_width.size() && geom::plausibleBeamWidth(m.beam_width[i]))
      r.beam_width = m.beam_width[i];
    else  // the reading is still usable, with the configured beam
      problems.push_back({"rejected.sonar_beam", field("SONAR_RING", "beam_width", i) + " = " +
                                                     (i < m.beam_width.size() ? num(m.beam_width[i]) : std::string("missing")) +
                                                     " (not in (0, pi) rad): the configured beam used"});
    if (r.sensor_id < 0 || r.sensor_id >= m.num_sensors) {
      r.valid = false;
      problems.push_back({"rejected.sonar_id", field("SONAR_RING", "sensor_id", i) + " = " +
                                                   std::to_string(r.sensor_id) + " (num_sensors " +
                                                   std::to_string(m.num_sensors) + ")"});
    } else if (!plausiblePose(m.mount[i])) {
      r.valid = false;
      problems.push_back({"rejected.sonar_mount", field("SONAR_RING", "mount", i) + " is not finite (or beyond " +
                                                      num(kMaxCoordinate) + " m)"});
    } else if (!r.no_echo && std::isinf(r.range) && r.range > 0) {
      // +inf: nothing came back (ROS REP 117's convention for a range sensor): as no_echo = 1.
      r.no_echo = true;
      r.range = range_max;
    } else if (!r.no_echo && !(std::isfinite(r.range) && r.range >= kMinSonarRange && r.range <= range_max)) {
      r.valid = false;
      const bool too_near = std::isfinite(r.range) && r.range >= 0 && r.range < kMinSonarRange;
      problems.push_back({"rejected.sonar_range",
                          field("SONAR_RING", "range", i) + " = " + num(r.range) +
                              (too_near ? " (nearer than any transducer hears, " + num(kMinSonarRange) +
                                              " m: a driver's \"no reading\"? send no_echo = 1)"
                                        : " (range_max " + num(m.range_max) + ")")});
    }
    g.readings.push_back(r);
  }
  return g;
}

line_map_t radarMapToMessage(const RadarMap& rm) {
  line_map_t m;
  m.utime = rm.utime;
  m.source_utime = rm.source_utime;
  m.robot_pose = toPoseMsg(rm.robot_pose);
  m.segments.reserve(rm.segments.size());  // (one allocation, not one per doubling)
  for (const RmSegment& s : rm.segments) {
    line_segment_t l;
    l.x0 = s.seg.a.x();
    l.y0 = s.seg.a.y();
    l.x1 = s.seg.b.x();
    l.y1 = s.seg.b.y();
    l.npoints = s.npoints;
    l.rms = static_cast<float>(s.rms);
    l.source = line_segment_t::SOURCE_LASER;
    l.last_supported_utime = rm.utime;
    m.segments.push_back(l);
  }
  m.nsegments = static_cast<int32_t>(m.segments.size());
  return m;
}

namespace {
// The widest beam a group's hypotheses used (the model's when the group is empty).
double widestBeam(const GroupComplement& g, const ComplementParams& p) {
  double b = 0;
  for (const ClassifiedReading& r : g.readings) b = std::max(b, r.beam_width);
  return b > 0 ? b : p.model.beam_width;
}
}  // namespace

hypothetical_scan_t hypothesisToMessage(const GroupComplement& g, const ComplementParams& p) {
  hypothetical_scan_t m;
  hypothesisToMessageInto(m, g, p);
  return m;
}

void hypothesisToMessageInto(hypothetical_scan_t& m, const GroupComplement& g, const ComplementParams& p) {
  m.utime = g.utime;
  m.group = static_cast<int16_t>(g.group);
  m.radar_map_utime = g.radar_map_utime;
  m.radar_map_stale = g.radar_map_stale ? 1 : 0;
  m.range_limit = static_cast<float>(p.model.range_limit);
  m.beam_width = static_cast<float>(widestBeam(g, p));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.sensor_id.clear();
  m.range.clear();
  m.sensor_pose.clear();
  m.sensor_id.reserve(g.readings.size());  // (one allocation per array, not one per doubling)
  m.range.reserve(g.readings.size());
  m.sensor_pose.reserve(g.readings.size());
  for (const ClassifiedReading& r : g.readings) {
    m.sensor_id.push_back(static_cast<int16_t>(r.sensor_id));
    m.range.push_back(static_cast<float>(r.hypothetical_range));
    m.sensor_pose.push_back(toPoseMsg(r.sensor_pose.value_or(geom::Pose2{nan, nan, nan})));
  }
  m.nreadings = static_cast<int32_t>(m.sensor_id.size());
}

complement_t complementToMessage(const GroupComplement& g, const ComplementParams& p) {
  complement_t m;
  complementToMessageInto(m, g, p);
  return m;
}

void complementToMessageInto(complement_t& m, const GroupComplement& g, const ComplementParams& p) {
  m.utime = g.utime;
  m.group = static_cast<int16_t>(g.group);
  m.radar_map_utime = g.radar_map_utime;
  m.radar_map_stale = g.radar_map_stale ? 1 : 0;
  m.tolerance = static_cast<float>(p.tolerance);
  m.beam_width = static_cast<float>(widestBeam(g, p));
  m.range_limit = static_cast<float>(p.model.range_limit);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.readings.clear();
  m.readings.reserve(g.readings.size());  // (one allocation, not one per doubling)
  for (const ClassifiedReading& r : g.readings) {
    complement_reading_t c;
    c.sensor_id = static_cast<int16_t>(r.sensor_id);
    c.cls = static_cast<int8_t>(r.cls);
    c.range = static_cast<float>(r.range);
    c.hypothetical_range = static_cast<float>(r.hypothetical_range);
    c.sensor_pose = toPoseMsg(r.sensor_pose.value_or(geom::Pose2{nan, nan, nan}));
    c.beam_width = static_cast<float>(r.beam_width > 0 ? r.beam_width : p.model.beam_width);
    const geom::Vec2 end = r.end.value_or(geom::Vec2(nan, nan));
    c.end_x = end.x();
    c.end_y = end.y();
    m.readings.push_back(c);
  }
  m.nreadings = static_cast<int32_t>(m.readings.size());
}

static_assert(static_cast<int8_t>(SonarClass::Complementary) == complement_reading_t::CLASS_COMPLEMENTARY &&
                  static_cast<int8_t>(SonarClass::Redundant) == complement_reading_t::CLASS_REDUNDANT &&
                  static_cast<int8_t>(SonarClass::False) == complement_reading_t::CLASS_FALSE &&
                  static_cast<int8_t>(SonarClass::Unverifiable) == complement_reading_t::CLASS_UNVERIFIABLE &&
                  static_cast<int8_t>(SonarClass::Invalid) == complement_reading_t::CLASS_INVALID &&
                  static_cast<int8_t>(SonarClass::OutsideView) == complement_reading_t::CLASS_OUTSIDE_VIEW &&
                  static_cast<int8_t>(SonarClass::SeenBefore) == complement_reading_t::CLASS_SEEN_BEFORE,
              "SonarClass must match complement_reading_t::CLASS_*");

}  // namespace lasonic::complement
