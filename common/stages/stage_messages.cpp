#include "stages/stage_messages.hpp"

#include <algorithm>

namespace lasonic {

int publishedOffset(const AccumulativeGridMap& agm, int published_size) {
  if (published_size <= 0 || published_size >= agm.size()) return 0;
  return agm.size() / 2 - published_size / 2;
}

grid_map_t gridMapMessage(const AccumulativeGridMap& agm, int64_t utime, const geom::Pose2& robot, int gp_threshold,
                          int published_size) {
  grid_map_t msg{};
  gridMapMessageInto(msg, agm, utime, robot, gp_threshold, published_size);
  return msg;
}

void gridMapMessageInto(grid_map_t& msg, const AccumulativeGridMap& agm, int64_t utime, const geom::Pose2& robot,
                        int gp_threshold, int published_size) {
  msg.utime = utime;
  msg.robot_pose = {robot.x, robot.y, robot.theta};
  const int w = published_size <= 0 ? agm.size() : std::min(published_size, agm.size());
  const int o = publishedOffset(agm, w);
  const geom::Vec2 origin = agm.cellCorner(o, o);
  msg.origin_x = origin.x();
  msg.origin_y = origin.y();
  msg.cell_size = static_cast<float>(agm.cellSize());
  msg.width = msg.height = w;
  msg.gp_threshold = gp_threshold;
  if (w == agm.size())
    agm.exportGrids(msg.g, msg.h, msg.gp);
  else
    agm.exportGrids(o, o, w, msg.g, msg.h, msg.gp);
  msg.heard.assign(msg.g.size(), int8_t{grid_map_t::HEARD_UNKNOWN});  // a caller that records it fills it in
  msg.ncells = static_cast<int32_t>(msg.g.size());
}

line_map_t lineMapMessage(const std::vector<CsmLine>& lines, int64_t utime, int64_t source_utime,
                          const geom::Pose2& robot) {
  line_map_t m{};
  m.utime = utime;
  m.source_utime = source_utime;
  m.robot_pose = {robot.x, robot.y, robot.theta};
  m.segments.reserve(lines.size());
  for (const CsmLine& l : lines) {
    line_segment_t s{};
    s.x0 = l.seg.a.x();
    s.y0 = l.seg.a.y();
    s.x1 = l.seg.b.x();
    s.y1 = l.seg.b.y();
    s.npoints = l.npoints;
    s.rms = static_cast<float>(l.rms);
    s.source = l.source == LineSource::Laser ? line_segment_t::SOURCE_LASER : line_segment_t::SOURCE_SONAR;
    s.last_supported_utime = l.last_supported_utime;
    m.segments.push_back(s);
  }
  m.nsegments = static_cast<int32_t>(m.segments.size());
  return m;
}

}  // namespace lasonic
