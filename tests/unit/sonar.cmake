# The simulated sonar (common/sim/sonar.cpp, sonar_model.hpp).
lasonic_add_gtest(test_sonar SOURCES test_sonar.cpp LIBS lasonic_sim)
