// lasonic-mrpt-peer --log LOG --scenario FILE [--config FILE] [--json FILE|-]
//
// A peer side by side (README "Evaluation", MRPT peer): MRPT's COccupancyGridMap2D is fed the
// same laser scans and sonar readings as lasonic (the log's raw channels, in time order), read out
// by the pilot's SectorMap at the times of the pilot's SECTOR_MAP messages, exactly like the
// evaluation's baselines, and scored against the same truth. Beside its accuracy it reports the
// time per update, MRPT's and lasonic's own stages on the same data (Release build, CPU time of
// this thread: a benchmark, not part of any result that must be reproducible).
//
// How the data are given to MRPT:
// - a LASER_SCAN becomes one CObservation2DRangeScan with the robot pose at the scan's last
//   reading: MRPT inserts a scan with one pose, so every reading is first moved (with the pose at
//   its own time) into the sensor frame at that pose and put into the beam of its bearing;
// - each sonar reading becomes its own CObservationRange (MRPT inserts a range observation with
//   the first sensor's pose for all its readings), cone = the reading's beam width, no echo =
//   sensed distance 0 (MRPT's convention: nothing inserted);
// - MRPT's own insertion defaults (maxOccupancyUpdateCertainty 0.65, invalid laser ranges as free
//   space), the grid resolution of the log-odds baseline (baselines.log_odds.cell_size) and its
//   read-out threshold (baselines.log_odds.occupied_threshold).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <iostream>
#include <numeric>
#include <string>
#include <vector>

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationRange.h>
#include <mrpt/poses/CPose3D.h>

#include "complement/complement.hpp"
#include "complement/complement_config.hpp"
#include "complement/radar_map.hpp"
#include "core/cli.hpp"
#include "core/config.hpp"
#include "eval/baselines.hpp"
#include "eval/evaluate.hpp"
#include "eval/observability.hpp"
#include "lcmio/eventlog.hpp"
#include "operational/agm.hpp"
#include "operational/sector_map.hpp"

namespace {

using namespace lasonic;
// The thread's CPU time: on a shared machine other processes' time slices do not count.
struct Clock {
  using time_point = double;  // [us]
  static time_point now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
  }
};

double usSince(Clock::time_point t0) { return Clock::now() - t0; }

// Times of one kind of update [us].
struct Timing {
  std::vector<double> us;
  void write(eval::Metrics& m, const std::string& key) {
    if (us.empty()) return;
    std::sort(us.begin(), us.end());
    m.set(key + ".median_us", us[us.size() / 2]);
    m.set(key + ".p90_us", us[std::min(us.size() - 1, us.size() * 9 / 10)]);
    m.set(key + ".mean_us", std::accumulate(us.begin(), us.end(), 0.0) / static_cast<double>(us.size()));
    m.set(key + ".count", static_cast<int64_t>(us.size()));
  }
};

mrpt::poses::CPose3D pose3(const geom::Pose2& p) { return {p.x, p.y, 0.0, p.theta, 0.0, 0.0}; }

// MRPT's cells around the robot as an OccupancyWindow (the AGM's layout), for the SectorMap. MRPT
// stores the probability of a cell being *free* (in log odds): an obstacle is a cell whose free
// probability is at most 1 - threshold.
void readWindow(const mrpt::maps::COccupancyGridMap2D& grid, const geom::Vec2& robot, double threshold,
                OccupancyWindow& w, std::vector<int>& column) {
  using Grid = mrpt::maps::COccupancyGridMap2D;
  const double c = w.cell_size;
  w.origin_x = static_cast<int64_t>(std::floor(robot.x() / c)) - w.size / 2;
  w.origin_y = static_cast<int64_t>(std::floor(robot.y() / c)) - w.size / 2;
  const Grid::cellType obstacle = Grid::p2l(static_cast<float>(1.0 - threshold));
  const int nx = static_cast<int>(grid.getSizeX()), ny = static_cast<int>(grid.getSizeY());
  column.resize(static_cast<size_t>(w.size));
  for (int ix = 0; ix < w.size; ++ix) column[static_cast<size_t>(ix)] = grid.x2idx((static_cast<double>(w.origin_x + ix) + 0.5) * c);
  for (int iy = 0; iy < w.size; ++iy) {
    uint8_t* out = w.occupied.data() + static_cast<size_t>(iy) * static_cast<size_t>(w.size);
    const int cy = grid.y2idx((static_cast<double>(w.origin_y + iy) + 0.5) * c);
    if (cy < 0 || cy >= ny) {
      std::fill(out, out + w.size, uint8_t{0});  // outside MRPT's grid: unknown
      continue;
    }
    const Grid::cellType* row = grid.getRow(cy);
    for (int ix = 0; ix < w.size; ++ix) {
      const int cx = column[static_cast<size_t>(ix)];
      out[ix] = cx >= 0 && cx < nx && row[cx] <= obstacle ? 1 : 0;
    }
  }
}

int run(const std::string& log_path, const std::string& scenario_path, const Config& root, const std::string& json) {
  const eval::BaselinesConfig cfg = eval::baselinesConfig(root);
  const complement::ComplementConfig ccfg = complement::complementConfig(root.section("complement"));
  complement::PingHistory pings;  // the earlier groups' pings, for late echoes (as ComplementStage)
  const sim::Scenario sc = sim::loadScenario(scenario_path);
  const eval::RunLog log = eval::loadRunLog(log_path);
  const eval::EvalOptions o;
  const eval::SectorTruthTable truth = eval::sectorTruthTable(log, sc, o);
  if (truth.maps.empty() || log.odometry.empty()) {
    std::cerr << "lasonic-mrpt-peer: " << log_path
              << " holds no scored SECTOR_MAP or no ODOMETRY (run it through lasonic-replay first)\n";
    return 2;
  }
  eval::Metrics m;
  m.set("scenario", sc.name);
  {  // lasonic's own maps, for the side-by-side table
    eval::Metrics own;
    eval::evalSectorMap(log, truth, o, own);
    for (const char* k : {"missed_rate", "observable_missed_rate", "false_alarm_rate", "false_alarm_share_of_reports",
                          "mae_m"})
      if (own.has(std::string("sector_map.") + k))
        m.set(std::string("lasonic.sector_map.") + k, own.number(std::string("sector_map.") + k));
  }

  const std::vector<size_t> order = eval::mapsInTimeOrder(log, truth);
  SectorMapParams rp = cfg.readout;
  const sector_map_t& first = log.sector_maps[truth.maps[order.front()]];
  rp.sectors = first.nsectors;
  if (std::isfinite(first.robot_radius) && first.robot_radius >= 0) rp.robot_radius = first.robot_radius;
  if (std::isfinite(first.max_range) && first.max_range > 0) rp.max_range = first.max_range;

  // MRPT's grid: the log-odds baseline's resolution, aligned to the global cell grid, around the
  // start (MRPT grows it as the robot drives on).
  const double res = cfg.log_odds.window.cell_size;
  const auto& od0 = log.odometry.front().pose;
  const auto edge = [res](double v) { return static_cast<float>(std::floor(v / res) * res); };
  mrpt::maps::COccupancyGridMap2D grid(edge(od0.x - 5.0), edge(od0.x + 5.0), edge(od0.y - 5.0), edge(od0.y + 5.0),
                                       static_cast<float>(res));
  OccupancyWindow window;
  std::vector<int> column;
  window.size = cfg.log_odds.window.size;
  window.cell_size = res;
  window.occupied.assign(static_cast<size_t>(window.size) * static_cast<size_t>(window.size), 0);
  SectorMap mrpt_map(rp);
  eval::SectorScore score;

  // lasonic's stages on the same data, for the time per update only: Radar Map per scan;
  // hypothetical scan + classification, AGM cycle (the readings' axis end points) and sector
  // map per firing group; the first sector map after a scan.
  std::optional<complement::RadarMap> rm;
  AccumulativeGridMap agm(cfg.naive_fusion.agm);
  SectorMap own_map(rp);
  Timing mrpt_scan, mrpt_group_insert, mrpt_readout, mrpt_group, own_scan, own_radar_map, own_scan_map, own_group;

  eval::RawChannelReplay replay(log);
  eval::RawChannelReplay::Handlers h;
  h.laser = [&](const laser_scan_t& msg, const complement::LaserScan& scan,
                const std::vector<complement::ScanPoint>& placed, int64_t newest) {
    const auto ref = replay.poses().at(newest);
    if (!ref) return;
    // MRPT: one pose per scan; readings moved into the sensor frame at that pose.
    const size_t n = scan.readings.size();
    const geom::Pose2 sensor_ref = ref->compose(scan.mount);
    std::vector<float> range(n, 0.0f);
    std::vector<char> valid(n, 0);
    std::vector<geom::Vec2> points;
    // The LaserScan's readings run counter-clockwise (a clockwise scan's reversed), from its first
    // reading's angle by |angle_increment|.
    const double angle_min = n > 0 ? scan.readings.front().angle : msg.angle_min;
    const double increment = std::abs(msg.angle_increment);
    for (size_t i = 0; i < n; ++i) {
      if (!placed[i].valid) continue;
      points.push_back(placed[i].p);
      const geom::Vec2 local = sensor_ref.inverseTransform(placed[i].p);
      // The bearing from the first reading's, in [-increment/2, 2 pi - increment/2): a view that
      // starts above -pi (a scanner whose angle_min is 0, say) reaches past atan2's pi.
      double from_first = std::atan2(local.y(), local.x()) - angle_min;
      from_first -= 2 * geom::kPi * std::floor((from_first + 0.5 * increment) / (2 * geom::kPi));
      auto k = static_cast<int64_t>(std::lround(from_first / increment));
      if (scan.full_circle) k = ((k % static_cast<int64_t>(n)) + static_cast<int64_t>(n)) % static_cast<int64_t>(n);
      if (k < 0 || k >= static_cast<int64_t>(n)) continue;
      const auto d = static_cast<float>(local.norm());
      const auto idx = static_cast<size_t>(k);
      if (!valid[idx] || d < range[idx]) {
        range[idx] = d;
        valid[idx] = 1;
      }
    }
    mrpt::obs::CObservation2DRangeScan obs;
    obs.resizeScan(n);
    for (size_t i = 0; i < n; ++i) {
      obs.setScanRange(i, range[i]);
      obs.setScanRangeValidity(i, valid[i] != 0);
    }
    obs.aperture = static_cast<float>(static_cast<double>(n) * increment);
    obs.rightToLeft = true;
    obs.maxRange = msg.range_max;
    // MRPT's beam i lies at -aperture/2 + i * aperture/n in its sensor frame.
    obs.sensorPose = mrpt::poses::CPose3D(scan.mount.x, scan.mount.y, 0.0,
                                          scan.mount.theta + angle_min + 0.5 * obs.aperture, 0.0, 0.0);
    const auto robot3 = pose3(*ref);
    auto t0 = Clock::now();
    grid.insertObservation(obs, robot3);
    mrpt_scan.us.push_back(usSince(t0));
    if (!points.empty()) mrpt_map.setLaserPoints(newest, points);

    t0 = Clock::now();
    rm = complement::extractRadarMap(scan, replay.poses(), ccfg.radar_map);  // (as ComplementStage)
    const double radar_map_us = usSince(t0);
    t0 = Clock::now();
    if (!points.empty()) own_map.setLaserPoints(newest, std::move(points));
    own_map.update(newest, *ref, agm);
    const double map_us = usSince(t0);
    own_radar_map.us.push_back(radar_map_us);
    own_scan_map.us.push_back(map_us);
    own_scan.us.push_back(radar_map_us + map_us);
  };
  h.sonar = [&](const sonar_ring_t& msg, const complement::SonarGroup& g, const std::optional<geom::Pose2>& robot) {
    mrpt_map.setSonarTime(msg.utime);
    if (!robot) return;
    const auto robot3 = pose3(*robot);
    double insert_us = 0;
    for (size_t i = 0; i < g.readings.size(); ++i) {
      const complement::SonarReading& r = g.readings[i];
      if (!r.valid) continue;
      mrpt::obs::CObservationRange obs;
      obs.minSensorDistance = 0.0f;
      obs.maxSensorDistance = msg.range_max;
      obs.sensorConeApperture = i < msg.beam_width.size() ? msg.beam_width[i]
                                                          : static_cast<float>(cfg.naive_fusion.placement.params.beam_width);
      mrpt::obs::CObservationRange::TMeasurement meas;
      meas.sensorID = static_cast<uint16_t>(r.sensor_id);
      meas.sensorPose = mrpt::math::TPose3D(r.mount.x, r.mount.y, 0.0, r.mount.theta, 0.0, 0.0);
      meas.sensedDistance = r.no_echo ? 0.0f : static_cast<float>(r.range);
      obs.sensedData.push_back(meas);
      const auto t0 = Clock::now();
      grid.insertObservation(obs, robot3);
      insert_us += usSince(t0);
    }
    mrpt_group_insert.us.push_back(insert_us);

    const auto t0 = Clock::now();
    const auto gc = complement::extractComplement(g, robot, rm ? &*rm : nullptr, ccfg.params,
                                                  pings.before(msg.utime, ccfg.params.late_echo_window_us));
    pings.add(gc);
    std::vector<geom::Vec2> hits;
    for (const auto& c : gc.readings)
      if ((c.cls == complement::SonarClass::Complementary || c.cls == complement::SonarClass::OutsideView) && c.end)
        hits.push_back(*c.end);
    agm.follow(robot->position(), replay.speed());
    agm.update(hits);
    own_map.setSonarTime(msg.utime);
    own_map.update(msg.utime, *robot, agm);
    own_group.us.push_back(usSince(t0));
  };

  for (const size_t j : order) {
    const sector_map_t& sm = log.sector_maps[truth.maps[j]];
    replay.advanceTo(sm.utime, h);
    if (truth.sectors(j) != rp.sectors) continue;
    const eval::SectorSample* s = truth.mapSamples(j);
    const auto pose = replay.poses().at(sm.utime);
    if (!pose) {
      for (int k = 0; k < rp.sectors; ++k) score.add(-1, s[k], o);
      continue;
    }
    const auto t0 = Clock::now();
    readWindow(grid, pose->position(), cfg.log_odds.occupied_threshold, window, column);
    const SectorMapState& st = mrpt_map.update(sm.utime, *pose, window);
    mrpt_readout.us.push_back(usSince(t0));
    for (size_t k = 0; k < st.distance.size(); ++k) score.add(st.distance[k], s[k], o);
  }
  score.write(m, "mrpt.sector_map", false, truth.materials);
  // One firing group = its range observations plus one sector-map read-out.
  const size_t groups = std::min(mrpt_group_insert.us.size(), mrpt_readout.us.size());
  for (size_t i = 0; i < groups; ++i) mrpt_group.us.push_back(mrpt_group_insert.us[i] + mrpt_readout.us[i]);
  mrpt_group.write(m, "timing.mrpt.firing_group");
  mrpt_group_insert.write(m, "timing.mrpt.range_observations");
  mrpt_readout.write(m, "timing.mrpt.sector_readout");
  mrpt_scan.write(m, "timing.mrpt.laser_scan");
  own_group.write(m, "timing.lasonic.firing_group");
  own_scan.write(m, "timing.lasonic.laser_scan");
  own_radar_map.write(m, "timing.lasonic.radar_map");
  own_scan_map.write(m, "timing.lasonic.sector_map_after_scan");

  if (json == "-") {
    std::cout << m.toJson();
    return 0;
  }
  std::cout << "lasonic-mrpt-peer: " << log_path << " (scenario " << sc.name << ")\n" << m.toTable();
  if (!json.empty()) {
    std::ofstream out(json);
    if (!out) {
      std::cerr << "lasonic-mrpt-peer: cannot write " << json << "\n";
      return 1;
    }
    out << m.toJson();
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lasonic-mrpt-peer: MRPT's occupancy grid on the same log, scored and timed beside lasonic"};
  std::string log_path, scenario_path, json_path;
  std::vector<std::string> config_files;
  app.add_option("--log", log_path, "LCM log run through lasonic-replay (raw channels, SECTOR_MAP, truth)")->required();
  app.add_option("--scenario", scenario_path, "scenario YAML the log was simulated from")->required();
  app.add_option("--config", config_files,
                 "YAML configuration (pilot, complement and baselines sections); repeat to layer overrides");
  app.add_option("--json", json_path, "also write the results as JSON to FILE ('-' = standard output)");
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;
  try {
    const Config root = Config::loadConfiguration(config_files);
    return run(log_path, scenario_path, root, json_path);
  } catch (const ConfigError& e) {
    std::cerr << "lasonic-mrpt-peer: " << e.what() << "\n";
    return 2;
  } catch (const LogError& e) {
    std::cerr << "lasonic-mrpt-peer: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "lasonic-mrpt-peer: " << e.what() << "\n";
    return 1;
  }
}
