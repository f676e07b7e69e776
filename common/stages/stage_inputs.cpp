#include "stages/stage_inputs.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

namespace lasonic {

namespace {
std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
std::string reading(size_t i, const char* field) {
  return "SONAR_COMPLEMENT.readings[" + std::to_string(i) + "]." + field;
}
}  // namespace

bool acceptOdometry(Node& node, PoseHistory& poses, const odometry_t& m) {
  node.noteMessageTime(m.utime);
  const std::pair<const char*, double> fields[] = {
      {"pose.x", m.pose.x}, {"pose.y", m.pose.y}, {"pose.theta", m.pose.theta}, {"v", m.v}};
  for (const auto& [name, value] : fields) {
    if (!std::isfinite(value)) {
      node.reportError("rejected.odometry_nan", std::string("ODOMETRY.") + name + " = " + num(value) + " (utime " +
                                                    std::to_string(m.utime) + "): dropped");
      return false;
    }
  }
  switch (poses.add(m.utime, {m.pose.x, m.pose.y, m.pose.theta})) {
    case PoseHistory::AddResult::Ok: return true;
    case PoseHistory::AddResult::Duplicate: node.count("odometry_duplicates"); return false;
    case PoseHistory::AddResult::WentBackwards:
      node.reportError("rejected.odometry_backwards", "ODOMETRY.utime = " + std::to_string(m.utime) +
                                                          " is older than the newest (" +
                                                          std::to_string(poses.newestTime()) + "): dropped");
      return false;
  }
  return false;
}

std::vector<GroupReading> complementGroup(Node& node, const complement_t& m) {
  std::vector<GroupReading> group;
  group.reserve(m.readings.size());
  for (size_t i = 0; i < m.readings.size(); ++i) {
    const complement_reading_t& r = m.readings[i];
    if (r.cls < complement_reading_t::CLASS_COMPLEMENTARY || r.cls > complement_reading_t::CLASS_INVALID) {
      node.reportError("rejected.complement_class",
                       reading(i, "cls") + " = " + std::to_string(r.cls) + " (unknown class): skipped");
      continue;
    }
    GroupReading g;
    g.sensor_id = r.sensor_id;
    if (r.cls == complement_reading_t::CLASS_COMPLEMENTARY) {
      const std::pair<const char*, double> fields[] = {{"range", r.range}, {"end_x", r.end_x}, {"end_y", r.end_y}};
      bool ok = true;
      for (const auto& [name, value] : fields) {
        if (ok && !std::isfinite(value)) {
          node.reportError("rejected.complement_nan", reading(i, name) + " = " + num(value) + ": skipped");
          ok = false;
        }
      }
      // A negative or absurd "echo" would also shift every neighbour's bearing.
      if (ok && (r.range < 0 || r.range > kMaxEchoRange)) {
        node.reportError("rejected.complement_range",
                         reading(i, "range") + " = " + num(r.range) + " (not in [0, 100] m): skipped");
        ok = false;
      }
      if (ok) {
        g.echo = true;
        g.e = SonarEcho{m.utime, r.range, {r.sensor_pose.x, r.sensor_pose.y, r.sensor_pose.theta}};
        g.axis_end = geom::Vec2(r.end_x, r.end_y);
      }
    }
    group.push_back(g);
  }
  return group;
}

}  // namespace lasonic
