# The simulator: scenario files, motion and odometry, ray casting, the laser model.
foreach(t test_scenario test_world test_laser)
  lasonic_add_gtest(${t} SOURCES ${CMAKE_CURRENT_LIST_DIR}/${t}.cpp LIBS lasonic_sim)
endforeach()
# test_scenario loads every shipped scenario.
target_compile_definitions(test_scenario PRIVATE LASONIC_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
# Random scenes: each loads as lasonic-sim loads it, with the shipped configuration.
lasonic_add_gtest(test_scene_generator SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_scene_generator.cpp LIBS lasonic_sim)
target_compile_definitions(test_scene_generator PRIVATE LASONIC_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
