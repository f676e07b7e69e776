// lasonic-replay: same input and config -> bit-identical output; derived channels recomputed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <utility>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/line_map_t.hpp>

#include "complement_fixture.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "scratch_dir.hpp"

using namespace lasonic;
namespace fs = std::filesystem;

namespace {

// 3 s of the Fig. 4 room with the robot driving: odometry 50 Hz, scans 5 Hz (100 ms each, logged
// when complete), six groups of four sonars every 30 ms, plus a stale RADAR_MAP to be dropped.
void writeFixtureLog(const std::string& path) {
  const auto world = fixture::fig4Room();
  const auto traj = fixture::moving({1.2, 1.8, 0.2}, 0, 0.4, 0.0, 0.2);
  std::vector<LogRecord> ev;
  auto add = [&](int64_t t, const char* ch, auto msg) { ev.push_back({t, ch, encodeMsg(msg)}); };
  const int64_t end = 3'000'000;
  for (int64_t t = 0; t <= end; t += 20'000) add(t, channels::ODOMETRY, fixture::odometryAt(traj, t));
  for (int64_t t = 0; t + 100'000 <= end; t += 200'000)
    add(t + 100'000, channels::LASER_SCAN, fixture::simulateScan(world, traj, t, 100'000));
  int group = 0;
  for (int64_t t = 10'000; t <= end; t += 30'000, group = (group + 1) % 6) {
    const auto truth = fixture::trueRing(world, traj(t));
    std::vector<int> ids;
    std::vector<double> ranges;
    for (int k = group; k < 24; k += 6) {
      ids.push_back(k);
      ranges.push_back(truth[static_cast<size_t>(k)]);
    }
    add(t, channels::SONAR_RING, fixture::sonarGroup(t, group, ids, ranges));
  }
  add(1'000'000, channels::RADAR_MAP, line_map_t{});
  std::stable_sort(ev.begin(), ev.end(), [](const LogRecord& a, const LogRecord& b) { return a.timestamp < b.timestamp; });
  LogWriter w(path);
  for (const auto& e : ev) w.writeRaw(e.channel, e.timestamp, e.data);
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(Replay, DeterministicAndRecomputesDerivedChannels) {
  const lasonic::fixture::ScratchDir scratch;
  const fs::path dir = scratch.path();
  const std::string in = (dir / "in.lcmlog").string();
  writeFixtureLog(in);
  // Twice with the default threads, then with the stages on one, two and three threads
  // (StagePipeline): all the same, byte for byte.
  const std::vector<std::pair<const char*, const char*>> runs = {
      {"a.lcmlog", ""}, {"b.lcmlog", ""}, {"t1.lcmlog", " --threads 1"}, {"t2.lcmlog", " --threads 2"}, {"t3.lcmlog", " --threads 3"}};
  for (const auto& [out, opts] : runs) {
    const std::string cmd = std::string(LASONIC_REPLAY_BIN) + opts + " --in " + in + " --out " + (dir / out).string() +
                            " > " + (dir / "replay.txt").string() + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp((dir / "replay.txt").string());
  }
  const std::string a = slurp((dir / "a.lcmlog").string());
  ASSERT_FALSE(a.empty());
  for (const auto& [out, opts] : runs)
    EXPECT_TRUE(a == slurp((dir / out).string())) << "replay output differs between runs: " << out << " (" << opts << ")";

  std::set<int64_t> input_times;
  for (const auto& e : LogReader::readAll(in)) input_times.insert(e.timestamp);
  int maps = 0, groups = 0, complementary = 0, stale = 0;
  for (const auto& e : LogReader::readAll((dir / "a.lcmlog").string())) {
    EXPECT_TRUE(input_times.count(e.timestamp)) << e.channel << " at " << e.timestamp;
    if (e.channel == channels::RADAR_MAP) {
      const auto m = decodeAs<line_map_t>(e.data);
      ASSERT_TRUE(m);
      EXPECT_GE(m->nsegments, 3);  // recomputed, not the empty one of the input
      ++maps;
    }
    if (e.channel == channels::SONAR_COMPLEMENT) {
      const auto c = decodeAs<complement_t>(e.data);
      ASSERT_TRUE(c);
      ++groups;
      stale += c->radar_map_stale;
      for (const auto& r : c->readings) complementary += r.cls == complement_reading_t::CLASS_COMPLEMENTARY;
    }
  }
  EXPECT_EQ(maps, 15);
  EXPECT_EQ(groups, 100);
  EXPECT_GT(complementary, 0);   // the door and the obstacle
  EXPECT_GT(stale, 0);           // the groups before the first scan
}
