# Tactical level: line generation, Current Sensor Map, NavigatorStage.
lasonic_add_gtest(test_line_generation SOURCES test_line_generation.cpp LIBS lasonic_tactical)
# Its pass-through and memory tests run the simulated pipeline for minutes of robot time (15-45 s
# each under the sanitizers): started first.
lasonic_add_gtest(test_navigator_stage SOURCES test_navigator_stage.cpp LIBS lasonic_stages lasonic_sim COST 20)
lasonic_add_gtest(test_look_weight SOURCES test_look_weight.cpp LIBS lasonic_tactical)
lasonic_add_gtest(test_laser_join SOURCES test_laser_join.cpp LIBS lasonic_tactical)
lasonic_add_gtest(test_laser_glint SOURCES test_laser_glint.cpp LIBS lasonic_tactical)
lasonic_add_gtest(test_scan_matcher SOURCES test_scan_matcher.cpp LIBS lasonic_tactical)
lasonic_add_gtest(test_pass_through SOURCES test_pass_through.cpp LIBS lasonic_tactical)
lasonic_add_gtest(test_echo_provenance SOURCES test_echo_provenance.cpp LIBS lasonic_tactical)
