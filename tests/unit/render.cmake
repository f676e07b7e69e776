# lasonic-render's library: snapshot of a moment of a log, Cairo drawing of the Fig. 8 panels.
if(TARGET lasonic_render)
  lasonic_add_gtest(test_render SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_render.cpp LIBS lasonic_render)
endif()
