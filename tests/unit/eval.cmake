lasonic_add_gtest(test_eval SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_eval.cpp LIBS lasonic_eval)
