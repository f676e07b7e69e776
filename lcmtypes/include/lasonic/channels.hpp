#pragma once
// lasonic's fixed LCM channel names (README "Channels"), beside the generated message types:
// installed with them (README "Installing"), so a program of one's own subscribes by the same
// names, e.g. lcm.subscribe(lasonic::channels::SECTOR_MAP, ...) with lasonic::sector_map_t.

namespace lasonic {

// Fixed channel names (README "Channels").
namespace channels {
inline constexpr const char* ODOMETRY = "ODOMETRY";
inline constexpr const char* LASER_SCAN = "LASER_SCAN";
inline constexpr const char* SONAR_RING = "SONAR_RING";
inline constexpr const char* SONAR_GEOMETRY = "SONAR_GEOMETRY";
inline constexpr const char* SIM_STATE = "SIM_STATE";
inline constexpr const char* SONAR_TRUTH = "SONAR_TRUTH";
inline constexpr const char* LASER_TRUTH = "LASER_TRUTH";
inline constexpr const char* RADAR_MAP = "RADAR_MAP";
inline constexpr const char* SONAR_HYPOTHESIS = "SONAR_HYPOTHESIS";
inline constexpr const char* SONAR_COMPLEMENT = "SONAR_COMPLEMENT";
inline constexpr const char* AGM_OPERATIONAL = "AGM_OPERATIONAL";
inline constexpr const char* SECTOR_MAP = "SECTOR_MAP";
inline constexpr const char* AGM_TACTICAL = "AGM_TACTICAL";
inline constexpr const char* AGM_LINES = "AGM_LINES";
inline constexpr const char* CURRENT_SENSOR_MAP = "CURRENT_SENSOR_MAP";
inline constexpr const char* PROCESS_STATUS = "PROCESS_STATUS";
}  // namespace channels

}  // namespace lasonic
