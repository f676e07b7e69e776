lasonic_add_gtest(test_launch SOURCES test_launch.cpp LIBS lasonic_launch)
