#pragma once
// Random indoor scenes (README "Random scenes"): scenes no one has looked at, so that a change to
// the method can be judged beyond the suite it was tuned on. Every value drawn has a physical
// range (room sizes of offices and labs, walking speeds, the robot's clearance), stated in
// scene_generator.cpp; nothing is drawn to suit the method.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lasonic::sim {

struct GeneratedScene {
  std::string name;          // random_<index>, three digits at least
  std::string yaml;          // the scenario file's text (README "Scenario format")
  bool pioneer = false;      // the Pioneer-type robot: score with the pipeline's pioneer overlay
  std::vector<std::string> materials;  // of the obstacles and movers placed, sorted, once each
  int movers = 0;
};

// Scene `index`: every draw derives from the index alone (one std::mt19937_64 stream, no library
// distribution, so the same index gives the same text on every platform). Empty when no robot
// path with clearance fits the drawn room and obstacles (rare; the next index is another scene).
std::optional<GeneratedScene> generateScene(uint64_t index);

}  // namespace lasonic::sim
