#pragma once
// The simulator's state with the robot at a pose and no movers, as the simulator and evaluation
// tests give it to the sensor models and the scorers.
#include <cstdint>

#include <lasonic/sim_state_t.hpp>

namespace lasonic::testing {

inline sim_state_t state(int64_t utime, double x = 0, double y = 0, double theta = 0) {
  sim_state_t st{};
  st.utime = utime;
  st.robot_pose.x = x;
  st.robot_pose.y = y;
  st.robot_pose.theta = theta;
  return st;
}

}  // namespace lasonic::testing
