# Complement extraction: RadarMap, HypotheticalScan, classification, the stage.
foreach(t test_radar_map test_hypothetical_scan test_complement test_pole_tracker test_dark_continuation)
  lasonic_add_gtest(${t} SOURCES ${t}.cpp LIBS lasonic_complement)
endforeach()
lasonic_add_gtest(test_complement_stage SOURCES test_complement_stage.cpp LIBS lasonic_stages)
lasonic_add_gtest(test_radar_map_memory SOURCES test_radar_map_memory.cpp LIBS lasonic_stages)

# Replay determinism: runs the real lasonic-replay twice on a fixture log and compares bytes.
lasonic_add_gtest(test_replay SOURCES test_replay.cpp LIBS lasonic_lcmio)
add_dependencies(test_replay lasonic-replay)
target_compile_definitions(test_replay PRIVATE LASONIC_REPLAY_BIN="$<TARGET_FILE:lasonic-replay>")
lasonic_add_gtest(test_boundaries SOURCES test_boundaries.cpp LIBS lasonic_complement lasonic_tactical lasonic_lcmio)
