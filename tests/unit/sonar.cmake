# The simulated sonar (common/sim/sonar.cpp, sonar_model.hpp; the physical profile:
# acoustics.cpp, sonar_physical.cpp).
foreach(t test_sonar test_acoustics test_sonar_physical)
  lasonic_add_gtest(${t} SOURCES ${CMAKE_CURRENT_LIST_DIR}/${t}.cpp LIBS lasonic_sim)
endforeach()
