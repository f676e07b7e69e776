#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"

#include <lasonic/odometry_t.hpp>
#include <lasonic/laser_scan_t.hpp>

using namespace lasonic;

TEST(Lengths, SetFromVectorsAndCheckParallelArrays) {
  laser_scan_t s{};
  s.ranges = {1, 2, 3};
  s.flags = {0, 0, 1};
  s.offset_us = {0, 10, 20};
  s.nranges = 99;  // stale count must be replaced
  setLengths(s);
  EXPECT_EQ(s.nranges, 3);
  s.flags.pop_back();
  EXPECT_THROW(setLengths(s), std::logic_error);
}

TEST(Node, TypedPubSubOverMemq) {
  Node node("test", "memq://", Node::Options{false, false});
  int got = 0;
  double x = 0;
  node.subscribe<odometry_t>("ODOMETRY", [&](const odometry_t& m) {
    ++got;
    x = m.pose.x;
  });
  odometry_t o{};
  o.utime = 5;
  o.pose.x = 1.25;
  node.publish("ODOMETRY", o);
  while (node.spinOnce(0) > 0) {
  }
  EXPECT_EQ(got, 1);
  EXPECT_DOUBLE_EQ(x, 1.25);
}

TEST(Node, DecodeErrorsAreCountedNotThrown) {
  Node node("test", "memq://", Node::Options{false, false});
  int got = 0;
  node.subscribe<odometry_t>("ODOMETRY", [&](const odometry_t&) { ++got; });
  const uint8_t junk[5] = {1, 2, 3, 4, 5};
  node.lcm().publish("ODOMETRY", junk, sizeof(junk));
  // A laser scan on the odometry channel: wrong fingerprint.
  laser_scan_t wrong{};
  node.publish("ODOMETRY", wrong);
  while (node.spinOnce(0) > 0) {
  }
  EXPECT_EQ(got, 0);
  EXPECT_EQ(node.counter("decode_errors.ODOMETRY"), 2);
  EXPECT_EQ(node.errors(), 2);
}

TEST(Node, HandlerExceptionsAreCaught) {
  Node node("test", "memq://", Node::Options{false, false});
  node.subscribe<odometry_t>("ODOMETRY", [&](const odometry_t&) { throw std::runtime_error("boom"); });
  odometry_t o{};
  node.publish("ODOMETRY", o);
  EXPECT_NO_THROW(while (node.spinOnce(0) > 0){});
  EXPECT_EQ(node.counter("handler_failures.ODOMETRY"), 1);
}

TEST(EventLog, WriteThenReadBack) {
  const std::string path = (std::filesystem::temp_directory_path() / "lasonic_test_eventlog.lcmlog").string();
  {
    LogWriter w(path);
    for (int i = 0; i < 3; ++i) {
      odometry_t o{};
      o.utime = i * 1000;
      o.pose.y = i;
      w.write("ODOMETRY", o.utime, o);
    }
  }
  const auto events = LogReader::readAll(path);
  ASSERT_EQ(events.size(), 3u);
  auto o = decodeAs<odometry_t>(events[2].data);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->utime, 2000);
  EXPECT_EQ(events[2].timestamp, 2000);
  EXPECT_FALSE(decodeAs<laser_scan_t>(events[0].data));
  std::remove(path.c_str());
  EXPECT_THROW(LogReader("/nonexistent/x.lcmlog"), LogError);
}
