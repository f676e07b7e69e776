// Observability of the sector map's truth (eval/observability.hpp): which surface point defines
// a sample's truth, which direct echoes located it and when, and the scores that use it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "eval/baselines.hpp"
#include "eval/evaluate.hpp"
#include "eval/observability.hpp"

using namespace lasonic;
using namespace lasonic::eval;
using geom::Vec2;

namespace {
// A 4 x 4 m plaster room (obstacle 0), a glass pane (obstacle 1) 1 m ahead of the robot at
// (2, 2) facing +x: x = 3, y in [1.5, 2.5], seen in sectors 20..27 (bearings -26.6..26.6 deg).
sim::Scenario glassRoom() {
  return sim::parseScenario(Config::fromString(R"(
name: t
duration_s: 10
seed: 1
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0,0],[4,0],[4,4],[0,4]]}
  - {shape: segment, material: glass, from: [3.0, 1.5], to: [3.0, 2.5]}
robot: {radius: 0.35, path: [[2,2],[2.5,2]], speed: 0.1}
)"));
}

sim_state_t state(int64_t utime) {
  sim_state_t s{};
  s.utime = utime;
  s.robot_pose.x = 2;
  s.robot_pose.y = 2;
  return s;
}

sonar_truth_t echo(int64_t utime, int8_t cause, int obstacle, double x, double y) {
  sonar_truth_t t{};
  t.utime = utime;
  sonar_cause_t c{};
  c.cause = cause;
  c.obstacle = obstacle;
  c.true_range = 1.0f;
  c.hit_x = x;
  c.hit_y = y;
  t.causes.push_back(c);
  t.nreadings = 1;
  return t;
}

// A map at utime reporting the truth everywhere except in sectors 24 and 27 (glass).
sector_map_t mapAt(int64_t utime, const std::vector<double>& truth) {
  sector_map_t sm{};
  sm.utime = utime;
  sm.robot_radius = 0.35f;
  sm.max_range = 3.0f;
  sm.nsectors = 48;
  sm.laser_age_s = sm.sonar_age_s = 0.1f;
  for (int k = 0; k < 48; ++k) {
    const float d = std::isfinite(truth[k]) && k != 24 && k != 27 ? static_cast<float>(truth[k]) : -1.0f;
    sm.distance.push_back(d);
    sm.laser_distance.push_back(d);
    sm.sonar_distance.push_back(-1);
    sm.source.push_back(int8_t{sector_map_t::SOURCE_LASER});
  }
  return sm;
}

RunLog glassLog(const sim::Scenario& sc) {
  RunLog log;
  log.sim_states = {state(0), state(2'000'000)};
  sim::WorldGeometry world(sc);
  const auto truth = trueSectorDistances(world, {2, 2, 0}, 0.35, 48, 3.0);
  log.sector_maps = {mapAt(500'000, truth), mapAt(1'000'000, truth)};
  // Before map A: a crosstalk reading that replaced a glass echo near sector 27's point (not a
  // located point: the pipeline never got it), and a wall echo there (another obstacle).
  log.sonar_truths.push_back(echo(400'000, sonar_cause_t::CAUSE_CROSSTALK, 1, 3.0, 2.42));
  log.sonar_truths.push_back(echo(450'000, sonar_cause_t::CAUSE_DIRECT, 0, 3.0, 2.42));
  // Between the maps: the glass heard face-on at (3, 2).
  log.sonar_truths.push_back(echo(600'000, sonar_cause_t::CAUSE_DIRECT, 1, 3.0, 2.0));
  // After map B: the glass near sector 27's point (too late for both maps).
  log.sonar_truths.push_back(echo(1'200'000, sonar_cause_t::CAUSE_DIRECT, 1, 3.0, 2.42));
  return log;
}
}  // namespace

TEST(LocatedPoints, SameObstacleWithinTheRadiusAtOrBeforeTheTime) {
  LocatedPoints lp(0.3);
  lp.add(1, 1000, {3.0, 2.0});
  lp.add(1, 500, {5.0, 5.0});  // out of time order: kept in order
  EXPECT_TRUE(lp.located(1, {3.0, 2.29}, 1000));
  EXPECT_TRUE(lp.located(1, {3.2, 2.2}, 5000));    // 0.28 m away
  EXPECT_FALSE(lp.located(1, {3.0, 2.31}, 5000));  // 0.31 m away
  EXPECT_FALSE(lp.located(1, {3.0, 2.0}, 999));    // not yet
  EXPECT_FALSE(lp.located(2, {3.0, 2.0}, 5000));   // another obstacle
  EXPECT_TRUE(lp.located(1, {5.1, 4.9}, 500));
  EXPECT_FALSE(lp.located(1, {5.1, 4.9}, 499));
  EXPECT_TRUE(lp.located(1, {2.71, 1.99}, 1000));  // across a bucket boundary
  EXPECT_EQ(lp.size(), 2u);
}

TEST(LocatedPoints, LastLocatedIsTheNewestEchoAtOrBeforeTheTime) {
  LocatedPoints lp(0.3);
  lp.add(1, 100, {3.0, 2.0});
  lp.add(1, 300, {3.0, 2.2});
  lp.add(1, 500, {3.0, 2.9});   // 0.9 m from the query: not this point's
  lp.add(1, 400, {2.75, 1.9});  // the neighbouring bucket (x < 2.7 is not; 2.75 is, 0.27 m)
  lp.add(2, 450, {3.0, 2.0});   // another obstacle
  EXPECT_EQ(lp.lastLocated(1, {3.0, 2.0}, 50), std::nullopt);
  EXPECT_EQ(lp.lastLocated(1, {3.0, 2.0}, 100), 100);
  EXPECT_EQ(lp.lastLocated(1, {3.0, 2.0}, 350), 300);
  EXPECT_EQ(lp.lastLocated(1, {3.0, 2.0}, 10'000), 400);
  EXPECT_EQ(lp.lastLocated(2, {3.0, 2.0}, 10'000), 450);
  EXPECT_EQ(lp.lastLocated(3, {3.0, 2.0}, 10'000), std::nullopt);
  for (int64_t t : {99, 100, 299, 300, 401, 10'000})
    EXPECT_EQ(lp.lastLocated(1, {3.0, 2.0}, t).has_value(), lp.located(1, {3.0, 2.0}, t)) << t;
  EXPECT_EQ(lp.countLocated(1, {3.0, 2.0}, 0, 10'000), 3);  // 100, 300, 400 (not 500: 0.9 m)
  EXPECT_EQ(lp.countLocated(1, {3.0, 2.0}, 100, 300), 2);   // both ends included
  EXPECT_EQ(lp.countLocated(1, {3.0, 2.0}, 101, 299), 0);
  EXPECT_EQ(lp.countLocated(1, {3.0, 2.0}, 300, 100), 0);
}

// A stretch two obstacles share (a box's side drawn on the wall) is one surface to both sensors,
// and the sector samples' truth counts it as the obstacle the laser sees best (the wall): an echo
// the simulator says came from the box locates that wall point too, as the evaluation counts it.
TEST(LocatedPoints, AnEchoFromASharedStretchLocatesTheObstacleItIsCountedAs) {
  const auto sc = sim::parseScenario(Config::fromString(R"(
name: t
duration_s: 10
seed: 1
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0,0],[4,0],[4,4],[0,4]]}
  - {shape: box, material: black_cardboard, center: [3.75, 2.0], size: [0.5, 0.4]}
robot: {radius: 0.35, path: [[2,2],[2.5,2]], speed: 0.1}
)"));
  ASSERT_EQ(sc.canonicalObstacle(1, {4.0, 2.0}), 0);
  ASSERT_EQ(sc.canonicalObstacle(1, {3.5, 2.0}), 1);  // the box's front face is its own
  const std::vector<sonar_truth_t> echoes = {echo(100, sonar_cause_t::CAUSE_DIRECT, 1, 4.0, 2.0),
                                             echo(200, sonar_cause_t::CAUSE_DIRECT, 1, 3.5, 1.9)};
  const double all = std::numeric_limits<double>::infinity();
  LocatedPoints as_counted(0.3), as_simulated(0.3);
  as_counted.addDirectEchoes(echoes, {}, all, &sc);
  as_simulated.addDirectEchoes(echoes, {}, all);
  EXPECT_TRUE(as_counted.located(0, {4.0, 2.1}, 100));
  EXPECT_FALSE(as_simulated.located(0, {4.0, 2.1}, 100));
  EXPECT_FALSE(as_counted.located(1, {4.0, 2.1}, 100));
  EXPECT_TRUE(as_counted.located(1, {3.5, 2.0}, 200));  // the front face stays the box's
  EXPECT_FALSE(as_counted.located(0, {3.5, 2.0}, 150));
}

TEST(SectorTruthTable, GlassIsObservableOnlyWhereAndAfterAnEchoLocatedIt) {
  const auto sc = glassRoom();
  const RunLog log = glassLog(sc);
  const auto table = sectorTruthTable(log, sc, EvalOptions{});
  ASSERT_EQ(table.maps.size(), 2u);
  const auto material = [&](size_t map, int k) {
    const int16_t i = table.mapSamples(map)[k].material;
    return i < 0 ? std::string("-") : table.materials[static_cast<size_t>(i)];
  };
  for (int k = 0; k < 48; ++k) EXPECT_EQ(material(0, k), k >= 20 && k <= 27 ? "glass" : "wall") << k;
  const SectorSample* a = table.mapSamples(0);
  const SectorSample* b = table.mapSamples(1);
  // Laser-reflecting truth (the plaster wall behind the robot) is observable from the start.
  EXPECT_TRUE(a[0].observable);
  EXPECT_TRUE(b[0].observable);
  // Glass: no echo yet in map A; in map B the sectors whose truth point lies within 0.3 m of
  // the echo's hit point (3, 2): 21..26 (points at |y - 2| <= 0.27 m), not 20 and 27 (0.41 m).
  for (int k = 20; k <= 27; ++k) {
    EXPECT_FALSE(a[k].observable) << k;
    EXPECT_EQ(b[k].observable, k >= 21 && k <= 26) << k;
  }
  EXPECT_NEAR(a[24].truth, 0.65, 1e-6);
  // How they are observable: the wall by the laser; the glass by one echo 0.4 s before map B,
  // within the operational memory (0.54 s); with a memory of 0.3 s, an older echo.
  EXPECT_EQ(b[0].cue, Cue::Laser);
  EXPECT_EQ(b[24].cue, Cue::EchoOnce);
  EXPECT_EQ(b[20].cue, Cue::None);
  EXPECT_EQ(a[24].cue, Cue::None);
  EvalOptions short_memory;
  short_memory.recent_echo_s = 0.3;
  EXPECT_EQ(sectorTruthTable(log, sc, short_memory).mapSamples(1)[24].cue, Cue::EchoOld);
  // A second echo near it before map B: heard repeatedly.
  RunLog twice = log;
  twice.sonar_truths.insert(twice.sonar_truths.begin() + 3, echo(700'000, sonar_cause_t::CAUSE_DIRECT, 1, 3.0, 2.05));
  EXPECT_EQ(sectorTruthTable(twice, sc, EvalOptions{}).mapSamples(1)[24].cue, Cue::EchoRepeated);
}

TEST(SectorTruthTable, AnEchoReadBeyondTheHypothesisLimitLocatesButTheMethodCannotUseIt) {
  const auto sc = glassRoom();
  RunLog log = glassLog(sc);
  // The glass echo between the maps read at 2.5 m (its true range; no SONAR_RING in the log):
  // beyond the hypothetical scan's 2.20 m, where the complement calls every reading unverifiable.
  log.sonar_truths[2].causes[0].true_range = 2.5f;
  const auto far = sectorTruthTable(log, sc, EvalOptions{});
  EXPECT_TRUE(far.mapSamples(1)[24].observable);  // observable all the same (the definition has no range)
  EXPECT_EQ(far.mapSamples(1)[24].cue, Cue::EchoFar);
  EXPECT_EQ(far.mapSamples(1)[20].cue, Cue::None);
  // The reading SONAR_RING reported decides, not the true range: 2.0 m is within the limit.
  sonar_ring_t ring{};
  ring.utime = log.sonar_truths[2].utime;
  ring.sensor_id = {log.sonar_truths[2].causes[0].sensor_id};
  ring.range = {2.0f};
  log.sonar_rings.push_back(ring);
  EXPECT_EQ(sectorTruthTable(log, sc, EvalOptions{}).mapSamples(1)[24].cue, Cue::EchoOnce);
  // A longer limit (the complement's, carried in SONAR_HYPOTHESIS when the log has it) admits 2.5 m.
  log.sonar_rings.clear();
  EvalOptions longer;
  longer.range_limit = 3.0;
  EXPECT_EQ(sectorTruthTable(log, sc, longer).mapSamples(1)[24].cue, Cue::EchoOnce);
  // The split is counted as a share of the observable misses (sector 24 of map B is missed).
  Metrics m;
  evalSectorMap(log, sc, EvalOptions{}, m);
  EXPECT_NEAR(m.number("sector_map.observable_missed_by_cue.echo_far"), 1.0, 1e-12);
  EXPECT_NEAR(m.number("sector_map.observable_missed_by_cue.echo_once"), 0.0, 1e-12);
}

TEST(SectorTruthTable, TheOperationalMemoryIsHMaxRingIntervalsOfTheRun) {
  const auto sc = glassRoom();
  RunLog log = glassLog(sc);  // the glass heard once at 0.6 s, map B at 1.0 s: 0.4 s before
  EvalOptions o;
  o.recent_echo_s = 0.3;
  // Without h_max or without rings: recent_echo_s as given (0.3 s: the echo is older).
  EXPECT_DOUBLE_EQ(operationalMemory(log, o), 0.3);
  EXPECT_EQ(sectorTruthTable(log, sc, o).mapSamples(1)[24].cue, Cue::EchoOld);
  o.operational_h_max = 5;
  EXPECT_DOUBLE_EQ(operationalMemory(log, o), 0.3);  // no SONAR_RING in the log
  // Rings every 100 ms (one out of order, one repeated: the median of the positive gaps).
  for (int64_t t : {0, 100'000, 200'000, 200'000, 300'000, 500'000, 400'000, 600'000}) {
    sonar_ring_t r{};
    r.utime = t;
    log.sonar_rings.push_back(r);
  }
  EXPECT_NEAR(operationalMemory(log, o), 0.5, 1e-12);  // 5 cycles of 0.1 s
  const auto table = sectorTruthTable(log, sc, o);
  EXPECT_NEAR(table.echo_memory_s, 0.5, 1e-12);
  EXPECT_EQ(table.mapSamples(1)[24].cue, Cue::EchoOnce);  // 0.4 s old: within the memory
  o.operational_h_max = 4;  // 0.4 s: exactly as old as the memory is long, still within it
  EXPECT_EQ(sectorTruthTable(log, sc, o).mapSamples(1)[24].cue, Cue::EchoOnce);
  o.operational_h_max = 3;                                 // 0.3 s: no longer
  EXPECT_EQ(sectorTruthTable(log, sc, o).mapSamples(1)[24].cue, Cue::EchoOld);
  // The run's config gives h_max: the pilot's (the code's default 18 without the key).
  EXPECT_EQ(evalOptions(Config::fromString("pilot: {agm: {h_max: 24}}\n")).operational_h_max, 24);
  EXPECT_EQ(evalOptions(Config::fromString("pilot: {}\n")).operational_h_max, 18);
  EXPECT_THROW(evalOptions(Config::fromString("pilot: {agm: {h_maks: 24}}\n")), ConfigError);
}

TEST(EvalSectorMap, ObservableSplitAndMissesByMaterial) {
  const auto sc = glassRoom();
  const RunLog log = glassLog(sc);
  sim::WorldGeometry world(sc);
  const auto truth = trueSectorDistances(world, {2, 2, 0}, 0.35, 48, 3.0);
  int within = 0;
  for (double t : truth) within += t <= 2.0;
  Metrics m;
  evalSectorMap(log, sc, EvalOptions{}, m);
  // Missed: sectors 24 and 27 of both maps. Unobservable: the 8 glass samples of map A and
  // sectors 20 and 27 of map B. Among the observable samples only map B's sector 24 is missed.
  const double n = 2.0 * within;
  EXPECT_NEAR(m.number("sector_map.missed_rate"), 4.0 / n, 1e-12);
  EXPECT_NEAR(m.number("sector_map.unobservable_share"), 10.0 / n, 1e-12);
  EXPECT_NEAR(m.number("sector_map.observable_missed_rate"), 1.0 / (n - 10.0), 1e-12);
  EXPECT_NEAR(m.number("sector_map.missed_by_material.glass"), 4.0 / 16.0, 1e-12);
  EXPECT_NEAR(m.number("sector_map.missed_by_material.wall"), 0.0, 1e-12);
  EXPECT_EQ(m.number("sector_map.samples.by_material.glass"), 16.0);
  EXPECT_EQ(m.number("sector_map.samples.observable"), n - 10.0);
  EXPECT_EQ(m.number("sector_map.samples.within_range"), n);
  EXPECT_EQ(m.number("sector_map.samples.missed"), 4.0);
  // (The baselines, laser_only included, are scored on the raw channels: eval_baselines.sh.)
  // The one observable miss was heard once, 0.4 s before its map: within the operational memory.
  EXPECT_NEAR(m.number("sector_map.observable_missed_by_cue.echo_once"), 1.0, 1e-12);
  EXPECT_NEAR(m.number("sector_map.observable_missed_by_cue.echo_repeated"), 0.0, 1e-12);
  EXPECT_NEAR(m.number("sector_map.observable_missed_by_cue.echo_old"), 0.0, 1e-12);
  EXPECT_NEAR(m.number("sector_map.observable_missed_by_cue.laser"), 0.0, 1e-12);
}

TEST(EvalBaselines, RunFromTheRawChannelsAtTheMapTimes) {
  // The robot stands still 1 m before the glass pane; the laser sees only the walls (the glass
  // is transparent), sensor 0 looks straight at the glass and hears it every firing group.
  const auto sc = glassRoom();
  RunLog log = glassLog(sc);
  for (int64_t t = 0; t <= 1'000'000; t += 20'000) {
    odometry_t od{};
    od.utime = t;
    od.pose.x = 2;
    od.pose.y = 2;
    log.odometry.push_back(od);
  }
  for (int64_t t = 0; t < 1'000'000; t += 30'000) {
    sonar_ring_t r{};
    r.utime = t + 10'000;
    r.num_sensors = 1;
    r.range_max = 3.0f;
    r.nreadings = 1;
    r.sensor_id = {0};
    r.range = {0.65f};  // from the ring at 0.35 m: the glass at 1.0 m from the centre
    r.no_echo = {0};
    pose2d_t mount{};
    mount.x = 0.35;
    r.mount = {mount};
    r.beam_width = {static_cast<float>(30.0 * geom::kPi / 180.0)};
    log.sonar_rings.push_back(r);
  }
  laser_scan_t scan{};
  scan.utime = 300'000;
  scan.angle_min = -geom::kPi;
  scan.angle_increment = geom::kPi / 360;
  scan.range_min = 0.05f;
  scan.range_max = 15.0f;
  sim::WorldGeometry world(sc);
  for (int i = 0; i < 720; ++i) {
    const double a = scan.angle_min + i * scan.angle_increment;
    // The laser passes through the glass.
    const auto hit = world.castRay({{2, 2}, geom::unitVector(a)}, 15.0,
                                   [](const sim::Material& mat) { return mat.laser != sim::LaserBehaviour::Reflect; });
    scan.ranges.push_back(hit ? static_cast<float>(hit->range) : 0.0f);
    scan.flags.push_back(hit ? int8_t{laser_scan_t::FLAG_OK} : int8_t{laser_scan_t::FLAG_NO_RETURN});
    scan.offset_us.push_back(0);
  }
  scan.nranges = 720;
  log.laser_scans.push_back(scan);
  log.laser_scans.push_back(scan);
  log.laser_scans.back().utime = 500'000;

  Metrics m;
  const auto table = sectorTruthTable(log, sc, EvalOptions{});
  evalBaselines(log, table, baselinesConfig(Config{}), EvalOptions{}, m);
  for (const char* name : {"sonar_himm", "naive_fusion", "log_odds"})
    for (const char* key : {"missed_rate", "observable_missed_rate", "false_alarm_rate", "false_alarm_share_of_reports"})
      EXPECT_TRUE(m.has(std::string("baselines.") + name + ".sector_map." + key)) << name << " " << key;
  // HIMM hears the glass but knows nothing of the walls: it misses most of the room.
  EXPECT_GT(m.number("baselines.sonar_himm.sector_map.missed_rate"), 0.5);
  // Naive fusion has the glass (from the sonar) and the walls (from the laser): nothing missed
  // but sectors whose glass no sensor covered (the one sensor's axis hits sector 24 only; the
  // copy rule adds 23 and 25).
  const double naive = m.number("baselines.naive_fusion.sector_map.missed_rate");
  EXPECT_LT(naive, m.number("baselines.sonar_himm.sector_map.missed_rate"));
  EXPECT_LT(naive, m.number("baselines.log_odds.sector_map.missed_rate") + 1e-12);
  // Every baseline is read out on the same samples, so its count of missed samples compares with
  // another's (and lasonic's) where the rates, printed to four decimals, tie; the count is the rate's.
  const double within = m.number("baselines.laser_only.sector_map.samples.within_range");
  EXPECT_GT(within, 0);
  for (const char* name : {"laser_only", "sonar_himm", "naive_fusion", "log_odds"}) {
    const std::string p = std::string("baselines.") + name + ".sector_map.";
    EXPECT_EQ(m.number(p + "samples.within_range"), within) << name;
    EXPECT_NEAR(m.number(p + "samples.missed") / within, m.number(p + "missed_rate"), 1e-12) << name;
  }
  EXPECT_GT(m.number("baselines.sonar_himm.sector_map.samples.missed"),
            m.number("baselines.naive_fusion.sector_map.samples.missed"));
  // Disabled: no keys.
  Metrics off;
  BaselinesConfig cfg = baselinesConfig(Config{});
  cfg.enabled = false;
  evalBaselines(log, table, cfg, EvalOptions{}, off);
  EXPECT_FALSE(off.has("baselines.sonar_himm.sector_map.missed_rate"));
}

TEST(BaselinesConfig, ReadsThePilotSectionAndChecksTheWindow) {
  const auto c = baselinesConfig(Config::fromString(R"(
pilot: {gp_threshold: 3, agm: {h_max: 7}}
baselines: {sonar_himm: {threshold: 6}, log_odds: {occupied_threshold: 0.8}}
)"));
  EXPECT_EQ(c.readout.gp_threshold, 3);
  EXPECT_EQ(c.naive_fusion.agm.h_max, 7);
  EXPECT_EQ(c.himm.threshold, 6);
  EXPECT_DOUBLE_EQ(c.log_odds.occupied_threshold, 0.8);
  // A window too small for the sector map's reach is refused, naming the key.
  try {
    baselinesConfig(Config::fromString("baselines: {log_odds: {size: 40}}"));
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("baselines.log_odds.size"), std::string::npos) << e.what();
  }
  EXPECT_THROW(baselinesConfig(Config::fromString("baselines: {mrpt: {}}")), ConfigError);
}

// The raw-channel replay hands a scan out once its latest reading is in; a reading whose time
// offset the pipeline rejects (outside the scan's sweep) delays nothing.
TEST(EvalBaselines, ARejectedTimeOffsetDoesNotDelayTheScan) {
  RunLog log;
  for (int64_t t = 0; t <= 1'000'000; t += 20'000) {
    odometry_t od{};
    od.utime = t;
    log.odometry.push_back(od);
  }
  laser_scan_t scan{};
  scan.utime = 300'000;
  scan.angle_min = -geom::kPi;
  scan.angle_increment = geom::kPi / 4;
  scan.range_min = 0.05f;
  scan.range_max = 15.0f;
  for (int i = 0; i < 8; ++i) {
    scan.ranges.push_back(2.0f);
    scan.flags.push_back(int8_t{laser_scan_t::FLAG_OK});
    scan.offset_us.push_back(i * 10'000);  // the latest at +70 ms
  }
  scan.offset_us[3] = 30'000'000;  // rejected: half a minute after the scan
  scan.nranges = 8;
  log.laser_scans.push_back(scan);
  RawChannelReplay replay(log);
  int scans = 0;
  RawChannelReplay::Handlers h;
  h.laser = [&scans](const laser_scan_t&, const complement::LaserScan&, const std::vector<complement::ScanPoint>&,
                     int64_t) { ++scans; };
  replay.advanceTo(369'999, h);
  EXPECT_EQ(scans, 0);
  replay.advanceTo(370'000, h);
  EXPECT_EQ(scans, 1);
}
