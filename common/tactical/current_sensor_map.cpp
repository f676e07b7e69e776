#include "tactical/current_sensor_map.hpp"

namespace lasonic {

void CurrentSensorMap::setRadarMap(const std::vector<CsmLine>& laser_lines, int64_t utime) {
  laser_ = laser_lines;
  for (CsmLine& l : laser_) {
    l.source = LineSource::Laser;
    if (l.last_supported_utime <= 0) l.last_supported_utime = utime;
  }
  rm_utime_ = utime;
}

void CurrentSensorMap::setAgmLines(const std::vector<AgmLine>& lines) {
  sonar_.clear();
  sonar_.reserve(lines.size());
  for (const AgmLine& a : lines) sonar_.push_back({a.seg, LineSource::Sonar, a.ncells, a.rms, a.support});
}

std::vector<CsmLine> CurrentSensorMap::lines() const {
  std::vector<CsmLine> out = laser_;
  out.insert(out.end(), sonar_.begin(), sonar_.end());
  return out;
}

}  // namespace lasonic
