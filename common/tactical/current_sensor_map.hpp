#pragma once
// Current Sensor Map (CSM; Jörg 1995, sec. 3.4, "Tactical abstraction level"): the tactical world
// model, the basis for long-term storage of the robot's geometric knowledge (which is out of
// this project's scope). It holds the lines of both complementary sources side by side, in the
// global (odometry) frame: the Radar Map's lines (what the laser sees) and the lines generated
// from the tactical AGM (what only the sonar sees: glass, mesh, black surfaces). Each line keeps
// its source and the time it was last supported by data, so a consumer can tell a line seen in
// the newest scan from one the sonar located seconds ago.
#include <cstdint>
#include <vector>

#include "core/geometry.hpp"
#include "tactical/line_generation.hpp"

namespace lasonic {

enum class LineSource : int8_t { Laser = 0, Sonar = 1 };

struct CsmLine {
  geom::Segment seg{geom::Vec2::Zero(), geom::Vec2::Zero()};  // global (odometry) frame
  LineSource source = LineSource::Laser;
  int npoints = 0;         // laser points / AGM cells the line was fitted to
  double rms = 0;          // [m]
  int64_t last_supported_utime = 0;
};

class CurrentSensorMap {
 public:
  // Replaces the laser lines with a new Radar Map's (supported at its scan time, utime).
  void setRadarMap(const std::vector<CsmLine>& laser_lines, int64_t utime);
  // Replaces the sonar lines with those generated from the tactical AGM (each with its support).
  void setAgmLines(const std::vector<AgmLine>& lines);

  int64_t radarMapUtime() const { return rm_utime_; }
  const std::vector<CsmLine>& laserLines() const { return laser_; }
  const std::vector<CsmLine>& sonarLines() const { return sonar_; }
  // Laser lines first, then sonar lines.
  std::vector<CsmLine> lines() const;

 private:
  std::vector<CsmLine> laser_, sonar_;
  int64_t rm_utime_ = 0;
};

}  // namespace lasonic
