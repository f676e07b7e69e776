# Operational level: AGM, Sector Map, echo bearing, PilotStage.
# Its comparison with the dense reference over random motion takes ~20 s under the sanitizers.
lasonic_add_gtest(test_agm SOURCES test_agm.cpp LIBS lasonic_operational COST 10)
lasonic_add_gtest(test_sector_map SOURCES test_sector_map.cpp LIBS lasonic_operational)
lasonic_add_gtest(test_sonar_bearing SOURCES test_sonar_bearing.cpp LIBS lasonic_operational)
lasonic_add_gtest(test_evidence_placement SOURCES test_evidence_placement.cpp LIBS lasonic_operational)
lasonic_add_gtest(test_pilot_stage SOURCES test_pilot_stage.cpp LIBS lasonic_stages)
lasonic_add_gtest(test_echo_placer SOURCES test_echo_placer.cpp LIBS lasonic_operational)
lasonic_add_gtest(test_mover_prediction SOURCES test_mover_prediction.cpp LIBS lasonic_operational)
lasonic_add_gtest(test_laser_memory SOURCES test_laser_memory.cpp LIBS lasonic_operational)
lasonic_add_gtest(test_remembered_on_lines SOURCES test_remembered_on_lines.cpp LIBS lasonic_operational)
lasonic_add_gtest(test_motion_confirmation SOURCES test_motion_confirmation.cpp LIBS lasonic_stages)
lasonic_add_gtest(test_boundaries_operational SOURCES test_boundaries_operational.cpp LIBS lasonic_operational)
