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

const std::vector<ScanPoint>& SharedPlacement::place(const LaserScan& scan, const PoseHistory& poses, int* no_pose) {
  if (have_ && sameScan(scan, scan_) && poses.sameAs(poses_)) {
    ++reused_;
  } else {
    points_ = placeReadings(scan, poses, &no_pose_);
    scan_ = scan;
    poses_ = poses;
    have_ = true;
    ++computed_;
  }
  if (no_pose) *no_pose = no_pose_;
  return points_;
}

}  // namespace lasonic::complement
