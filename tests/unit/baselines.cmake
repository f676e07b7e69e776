# Baseline mappers of the evaluation (HIMM, log-odds grid, naive fusion) and their window.
lasonic_add_gtest(test_baselines SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_baselines.cpp LIBS lasonic_baselines lasonic_complement)
