# The simulator: scenario files, motion and odometry, ray casting, the laser model.
foreach(t test_scenario test_world test_laser)
  lasonic_add_gtest(${t} SOURCES ${CMAKE_CURRENT_LIST_DIR}/${t}.cpp LIBS lasonic_sim)
endforeach()
# test_scenario loads every shipped scenario.
target_compile_definitions(test_scenario PRIVATE LASONIC_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
# Random scenes: each loads as lasonic-sim loads it, with the shipped configuration.
lasonic_add_gtest(test_scene_generator SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_scene_generator.cpp LIBS lasonic_sim)
target_compile_definitions(test_scene_generator PRIVATE LASONIC_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
# The simulator's executables at start-up: bad command lines and scenarios exit 2 (never abort),
# and no output overwrites an input.
lasonic_add_gtest(test_sim_cli SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_sim_cli.cpp)
add_dependencies(test_sim_cli lasonic-sim lasonic-sim-world lasonic-laser-driver lasonic-sonar-driver lasonic-scenegen)
target_compile_definitions(test_sim_cli PRIVATE LASONIC_BIN_DIR="${CMAKE_BINARY_DIR}/bin"
                                                LASONIC_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
if(TARGET lasonic-render)
  add_dependencies(test_sim_cli lasonic-render)
  target_compile_definitions(test_sim_cli PRIVATE LASONIC_RENDER_BIN="$<TARGET_FILE:lasonic-render>")
endif()
