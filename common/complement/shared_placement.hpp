#pragma once
// Placing a laser scan's readings (placeReadings: each reading with the pose interpolated at its
// own time) is a function of the scan and the odometry history alone. Where the complement and
// pilot stages run in one process (lasonic-replay), each keeps its own history of the same
// ODOMETRY messages and places the same scan: the second can take the first one's result instead
// of repeating it (about a fifth of a scan's work). The stored result is used only when the scan
// and the history are, bit for bit, the ones it was computed from -- then it is exactly what
// placeReadings would return -- and is computed afresh otherwise. The live processes each run
// one stage and do not use it.
#include <cstdint>
#include <optional>
#include <vector>

#include <lasonic/laser_scan_t.hpp>

#include "complement/messages.hpp"
#include "complement/radar_map.hpp"
#include "core/pose_history.hpp"

namespace lasonic::complement {

class SharedPlacement {
 public:
  // laserScanFromMessage(m, problems) -- the other per-scan work the two stages repeat: the
  // previous call's scan (and its problems, appended again) when m is the same message bit for
  // bit, computed afresh otherwise. The reference is valid until the next call.
  const std::optional<LaserScan>& scanFrom(const laser_scan_t& m, std::vector<InputProblem>& problems);
  // placeReadings(scan, poses, no_pose). The reference is valid until the next call.
  const std::vector<ScanPoint>& place(const LaserScan& scan, const PoseHistory& poses, int* no_pose = nullptr);
  int64_t reused() const { return reused_; }      // calls answered from the stored result
  int64_t computed() const { return computed_; }  // calls that placed the readings

 private:
  bool have_msg_ = false;
  laser_scan_t msg_;  // what scan_from_msg_ was made from
  std::optional<LaserScan> scan_from_msg_;
  std::vector<InputProblem> msg_problems_;
  uint64_t msg_generation_ = 0;  // counts the scans scanFrom computed
  // What the stored result was computed from: scanFrom's scan of one generation (known equal to
  // it as long as no other was computed since, without a copy or a comparison), or a copy.
  enum class From { Nothing, Message, Copy } from_ = From::Nothing;
  uint64_t from_generation_ = 0;
  LaserScan scan_;     // (From::Copy)
  PoseHistory poses_;
  std::vector<ScanPoint> points_;
  int no_pose_ = 0;
  int64_t reused_ = 0, computed_ = 0;
};

// The same scan, bit for bit (times, angles, ranges, flags, the mount).
bool sameScan(const LaserScan& a, const LaserScan& b);

}  // namespace lasonic::complement
