lasonic_add_gtest(test_eval SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_eval.cpp LIBS lasonic_eval)
lasonic_add_gtest(test_observability SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_observability.cpp LIBS lasonic_eval)
lasonic_add_gtest(test_laser_seen SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_laser_seen.cpp LIBS lasonic_eval)
