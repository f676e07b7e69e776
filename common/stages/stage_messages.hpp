#pragma once
// Output messages shared by the stages: an AGM window as grid_map_t, lines as line_map_t.
#include <cstdint>
#include <vector>

#include <lasonic/grid_map_t.hpp>
#include <lasonic/line_map_t.hpp>

#include "core/geometry.hpp"
#include "operational/agm.hpp"
#include "tactical/current_sensor_map.hpp"

namespace lasonic {

// AGM_OPERATIONAL / AGM_TACTICAL: the window's G, H and Gp, its origin and the robot pose.
// published_size > 0 (at most the window's size): only the published_size x published_size cells
// about the window's centre (the robot is within the re-centring limit of it), as a window of
// their own.
grid_map_t gridMapMessage(const AccumulativeGridMap& agm, int64_t utime, const geom::Pose2& robot, int gp_threshold,
                          int published_size = 0);
// The same into a message kept from map to map: its arrays keep their storage (a stage publishing
// a 100 x 100 window at 2 Hz would otherwise allocate and first-touch 90 kB each time).
void gridMapMessageInto(grid_map_t& msg, const AccumulativeGridMap& agm, int64_t utime, const geom::Pose2& robot,
                        int gp_threshold, int published_size = 0);
// Window cell of the published sub-window's cell (0, 0) (both axes).
int publishedOffset(const AccumulativeGridMap& agm, int published_size);

// AGM_LINES / CURRENT_SENSOR_MAP.
line_map_t lineMapMessage(const std::vector<CsmLine>& lines, int64_t utime, int64_t source_utime,
                          const geom::Pose2& robot);

}  // namespace lasonic
