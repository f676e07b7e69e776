#include "complement/shared_placement.hpp"

#include <cstring>

namespace lasonic::complement {

namespace {
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool samePose(const geom::Pose2& a, const geom::Pose2& b) {
  return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.theta, b.theta);
}
}  // namespace

bool sameScan(const LaserScan& a, const LaserScan& b) {
  if (a.utime != b.utime || a.full_circle != b.full_circle || !samePose(a.mount, b.mount) ||
      a.readings.size() != b.readings.size())
    return false;
  for (size_t i = 0; i < a.readings.size(); ++i) {
    const LaserReading& r = a.readings[i];
    const LaserReading& s = b.readings[i];
    if (r.utime != s.utime || r.valid != s.valid || !sameBits(r.angle, s.angle) || !sameBits(r.range, s.range))
      return false;
  }
  return true;
}

namespace {
template <typename T>
bool sameArray(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}
bool sameFloatBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
// Every field, bit for bit.
bool sameMessage(const laser_scan_t& a, const laser_scan_t& b) {
  return a.utime == b.utime && a.seq == b.seq && sameBits(a.mount.x, b.mount.x) && sameBits(a.mount.y, b.mount.y) &&
         sameBits(a.mount.theta, b.mount.theta) && sameBits(a.angle_min, b.angle_min) &&
         sameBits(a.angle_increment, b.angle_increment) && sameFloatBits(a.range_min, b.range_min) &&
         sameFloatBits(a.range_max, b.range_max) && a.nranges == b.nranges && sameArray(a.ranges, b.ranges) &&
         sameArray(a.flags, b.flags) && sameArray(a.offset_us, b.offset_us);
}
}  // namespace

const std::optional<LaserScan>& SharedPlacement::scanFrom(const laser_scan_t& m, std::vector<InputProblem>& problems) {
  if (!have_msg_ || !sameMessage(m, msg_)) {
    msg_problems_.clear();
    laserScanFromMessageInto(m, msg_problems_, scan_from_msg_);
    ++msg_generation_;
    msg_ = m;
    have_msg_ = true;
  }
  problems.insert(problems.end(), msg_problems_.begin(), msg_problems_.end());
  return scan_from_msg_;
}

const std::vector<ScanPoint>& SharedPlacement::place(const LaserScan& scan, const PoseHistory& poses, int* no_pose) {
  // The scan scanFrom returned (the stages pass it on) is the one the result was computed from
  // if no other was computed since; any other scan is compared with a copy.
  const bool from_message = scan_from_msg_ && &scan == &*scan_from_msg_;
  const bool same_scan = from_message ? from_ == From::Message && from_generation_ == msg_generation_
                                      : from_ == From::Copy && sameScan(scan, scan_);
  if (same_scan && poses.sameAs(poses_)) {
    ++reused_;
  } else {
    placeReadingsInto(scan, poses, points_, &no_pose_);
    if (from_message) {
      from_ = From::Message;
      from_generation_ = msg_generation_;
    } else {
      from_ = From::Copy;
      scan_ = scan;
    }
    poses_ = poses;
    ++computed_;
  }
  if (no_pose) *no_pose = no_pose_;
  return points_;
}

}  // namespace lasonic::complement
