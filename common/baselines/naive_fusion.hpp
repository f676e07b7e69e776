#pragma once
// Naive fusion: every sonar echo into the operational AGM, without complement extraction -- the
// evaluation's baseline that shows what the laser's verification of the sonar is worth (README
// "Evaluation", baselines). It is the pilot's operational level with every echo taken as a
// complementary reading: the same AGM parameters, the same one-cell placement of a reading
// (operational/echo_placer.hpp), one update cycle per firing group. A specular (too long)
// reading, which complement extraction rejects, therefore lands in the grid as a ghost, and an
// echo from a laser-visible wall seen obliquely is placed on the axis in front of the wall.
#include <cstdint>
#include <optional>
#include <vector>

#include "operational/agm.hpp"
#include "operational/echo_placer.hpp"
#include "operational/sonar_bearing.hpp"

namespace lasonic::baselines {

struct NaiveFusionParams {
  AgmParams agm;                  // the pilot's (pilot.agm)
  double h_max_ring_cycles = 0;   // the pilot's: h_max in ring cycles once counted (0: agm.h_max)
  EchoPlacementConfig placement;  // the pilot's
};

class NaiveFusion {
 public:
  explicit NaiveFusion(const NaiveFusionParams& p);

  struct Reading {
    int sensor_id = 0;
    geom::Pose2 sensor;  // global pose at the firing time (acoustic axis along theta)
    double range = 0;    // [m]
    bool echo = false;   // false: no echo (or an unusable reading)
    double beam_width = 0;  // [rad] the transducer's (SONAR_RING); 0: the placement's configured one
  };
  // One firing group = one AGM update cycle. robot: the robot's position at the firing time
  // (nullopt: unknown, the window stays), speed: for the re-centring rule. Returns the hits
  // that fell inside the window. group_id: the firing group's id, counted as the pilot counts the
  // ring's groups for its memory (h_max_ring_cycles; -1: not counted).
  int insertGroup(int64_t utime, const std::vector<Reading>& readings, const std::optional<geom::Vec2>& robot,
                  double speed, int group_id = -1);

  const AccumulativeGridMap& agm() const { return agm_; }

 private:
  NaiveFusionParams p_;
  AccumulativeGridMap agm_;
  EchoPlacer placer_;
  RingGroups ring_groups_;
};

}  // namespace lasonic::baselines
