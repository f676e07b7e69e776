// lasonic-render's library: what a moment of a log holds (SnapshotCollector, scanLog) and the
// Cairo drawing of the Fig. 8 panels, checked on the pixels.
#include <gtest/gtest.h>

#include <cairo.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>

#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "render/fig8.hpp"
#include "render/snapshot.hpp"
#include "scratch_dir.hpp"

using namespace lasonic;
using namespace lasonic::render;

namespace {

template <typename T>
LogRecord record(const std::string& channel, T msg) {
  return {msg.utime, channel, encodeMsg(msg)};
}

odometry_t odom(int64_t t, double x, double y, double th) {
  odometry_t o{};
  o.utime = t;
  o.pose.x = x;
  o.pose.y = y;
  o.pose.theta = th;
  return o;
}

line_map_t lines(int64_t t, std::vector<std::array<double, 4>> segs, int8_t source = line_segment_t::SOURCE_LASER) {
  line_map_t m{};
  m.utime = t;
  for (const auto& s : segs) {
    line_segment_t sg{};
    sg.x0 = s[0];
    sg.y0 = s[1];
    sg.x1 = s[2];
    sg.y1 = s[3];
    sg.source = source;
    m.segments.push_back(sg);
  }
  setLengths(m);
  return m;
}

sonar_ring_t ring(int64_t t, std::vector<int> ids, std::vector<float> ranges) {
  sonar_ring_t r{};
  r.utime = t;
  r.range_max = 3.0f;
  for (size_t i = 0; i < ids.size(); ++i) {
    r.sensor_id.push_back(static_cast<int16_t>(ids[i]));
    r.range.push_back(ranges[i]);
    r.no_echo.push_back(0);
    pose2d_t m{};
    m.x = 0.35 * std::cos(ids[i] * geom::kPi / 12);
    m.y = 0.35 * std::sin(ids[i] * geom::kPi / 12);
    m.theta = ids[i] * geom::kPi / 12;
    r.mount.push_back(m);
    r.beam_width.push_back(static_cast<float>(geom::deg2rad(30)));
  }
  setLengths(r);
  return r;
}

grid_map_t grid(int64_t t, double ox, double oy, double cell, int w, int h) {
  grid_map_t g{};
  g.utime = t;
  g.origin_x = ox;
  g.origin_y = oy;
  g.cell_size = static_cast<float>(cell);
  g.width = w;
  g.height = h;
  g.gp_threshold = 2;
  g.g.assign(static_cast<size_t>(w * h), 0);
  g.h.assign(static_cast<size_t>(w * h), 0);
  g.gp.assign(static_cast<size_t>(w * h), 0);
  setLengths(g);
  return g;
}

// ---- pixels
struct Image {
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface{nullptr, cairo_surface_destroy};
  int width = 0, height = 0;
  // 0xRRGGBB
  uint32_t at(double x, double y) const {
    const auto* data = cairo_image_surface_get_data(surface.get());
    const int stride = cairo_image_surface_get_stride(surface.get());
    const int ix = static_cast<int>(x), iy = static_cast<int>(y);
    return *reinterpret_cast<const uint32_t*>(data + iy * stride + 4 * ix) & 0xffffff;
  }
  int r(double x, double y) const { return static_cast<int>((at(x, y) >> 16) & 0xff); }
  int g(double x, double y) const { return static_cast<int>((at(x, y) >> 8) & 0xff); }
  int b(double x, double y) const { return static_cast<int>(at(x, y) & 0xff); }
};

Image draw(const Snapshot& s, std::vector<PanelStatus>& status, const sim::Scenario* sc = nullptr,
           const RenderOptions& o = {}) {
  Image im;
  const auto size = fig8Size(o);
  im.width = size.width;
  im.height = size.height;
  im.surface.reset(cairo_image_surface_create(CAIRO_FORMAT_RGB24, size.width, size.height));
  cairo_t* cr = cairo_create(im.surface.get());
  status = drawFig8(cr, s, sc, o);
  cairo_destroy(cr);
  cairo_surface_flush(im.surface.get());
  return im;
}

const PanelStatus& panel(const std::vector<PanelStatus>& st, const std::string& letter) {
  for (const auto& p : st)
    if (p.letter == letter) return p;
  throw std::runtime_error("no panel " + letter);
}

}  // namespace

// Cairo's and fontconfig's caches are freed after the last test (a clean leak check).
class ReleaseCairo : public ::testing::Environment {
 public:
  void TearDown() override { releaseStaticData(); }
};
const auto* const kReleaseCairo = ::testing::AddGlobalTestEnvironment(new ReleaseCairo);

// ------------------------------------------------------------------------------ snapshot

TEST(SnapshotCollector, NewestAtOrBeforeEvenOutOfOrder) {
  SnapshotCollector c;
  ASSERT_TRUE(c.add(record(channels::RADAR_MAP, lines(3'000'000, {{0, 0, 1, 0}}))));
  ASSERT_TRUE(c.add(record(channels::RADAR_MAP, lines(1'000'000, {{0, 0, 2, 0}}))));  // late in the log
  ASSERT_TRUE(c.add(record(channels::RADAR_MAP, lines(2'000'000, {{0, 0, 3, 0}}))));
  EXPECT_FALSE(c.at(999'999).radar_map);
  EXPECT_DOUBLE_EQ(c.at(1'500'000).radar_map->segments[0].x1, 2.0);
  EXPECT_DOUBLE_EQ(c.at(2'000'000).radar_map->segments[0].x1, 3.0);
  EXPECT_DOUBLE_EQ(c.at(9'000'000).radar_map->segments[0].x1, 1.0);  // held, however old
}

TEST(SnapshotCollector, ForgetKeepsEachChannelsNewest) {
  SnapshotCollector c;
  for (int k = 1; k <= 5; ++k) c.add(record(channels::RADAR_MAP, lines(k * 1'000'000, {{0, 0, double(k), 0}})));
  c.forget(4'500'000);
  EXPECT_DOUBLE_EQ(c.at(4'600'000).radar_map->segments[0].x1, 4.0);
  EXPECT_DOUBLE_EQ(c.at(6'000'000).radar_map->segments[0].x1, 5.0);
}

TEST(SnapshotCollector, RejectsUndecodableAndTimeless) {
  SnapshotCollector c;
  EXPECT_FALSE(c.add({1, channels::SECTOR_MAP, {1, 2, 3, 4, 5}}));
  auto rm = record(channels::RADAR_MAP, lines(1'000'000, {{0, 0, 1, 0}}));
  rm.data.resize(rm.data.size() - 3);  // truncated
  EXPECT_FALSE(c.add(rm));
  EXPECT_FALSE(c.add(record(channels::ODOMETRY, odom(0, 0, 0, 0))));  // no message time
  EXPECT_FALSE(c.add({1, "SOMETHING_ELSE", {1, 2}}));                 // ignored, not counted
  EXPECT_EQ(c.rejected(), 3);
}

TEST(SnapshotCollector, SonarBeamsPlacedWithOdometryAtFiringTime) {
  SnapshotCollector c;
  c.add(record(channels::ODOMETRY, odom(1'000'000, 0, 0, 0)));
  c.add(record(channels::ODOMETRY, odom(2'000'000, 1, 0, geom::kPi / 2)));
  // Sensor 0 looks ahead; fired half-way: robot at (0.5, 0) heading 45 deg.
  c.add(record(channels::SONAR_RING, ring(1'500'000, {0, 6}, {1.0f, 2.0f})));
  c.add(record(channels::SONAR_RING, ring(1'600'000, {0}, {1.5f})));  // sensor 0 again, newer
  const auto s = c.at(1'700'000);
  ASSERT_TRUE(s.robot);
  EXPECT_NEAR(s.robot->x, 0.7, 1e-9);
  ASSERT_EQ(s.sonar.size(), 2u);
  const SonarBeam* b0 = nullptr;
  for (const auto& b : s.sonar)
    if (b.sensor_id == 0) b0 = &b;
  ASSERT_TRUE(b0);
  EXPECT_FLOAT_EQ(static_cast<float>(b0->range), 1.5f);  // the newest reading of sensor 0
  EXPECT_EQ(b0->utime, 1'600'000);
  const double th = 0.6 * geom::kPi / 2;
  EXPECT_NEAR(b0->pose.x, 0.6 + 0.35 * std::cos(th), 1e-9);
  EXPECT_NEAR(b0->pose.y, 0.35 * std::sin(th), 1e-9);
  EXPECT_NEAR(b0->pose.theta, th, 1e-9);
  // Readings older than the window are not "the current scan".
  EXPECT_TRUE(c.at(3'000'000).sonar.empty());
}

TEST(SnapshotCollector, TheNavigatorsMapsComeIntoTheOdometryFrame) {
  // The navigator (scan matching) holds a line at its x = 3.2, and says the robot is at its
  // (1.2, 0) heading 0.1 rad; the odometry has the robot at (1, 0) heading 0: in the odometry
  // frame the line is where the robot's view of it says.
  SnapshotCollector c;
  c.add(record(channels::ODOMETRY, odom(1'000'000, 1, 0, 0)));
  c.add(record(channels::ODOMETRY, odom(2'000'000, 1, 0, 0)));
  line_map_t csm = lines(1'500'000, {{3.2, -1, 3.2, 1}}, line_segment_t::SOURCE_SONAR);
  csm.robot_pose = {1.2, 0.0, 0.1};
  c.add(record(channels::CURRENT_SENSOR_MAP, csm));
  grid_map_t g{};
  g.utime = 1'500'000;
  g.robot_pose = {1.2, 0.0, 0.1};
  g.cell_size = 0.1f;
  g.width = g.height = 1;
  g.g.assign(1, 0);
  g.h.assign(1, 0);
  g.gp.assign(1, 0);
  setLengths(g);
  c.add(record(channels::AGM_TACTICAL, g));
  const auto s = c.at(1'600'000);
  ASSERT_TRUE(s.current_sensor_map);
  const geom::Pose2 odo_from_nav = geom::Pose2{1, 0, 0}.compose(geom::Pose2{1.2, 0, 0.1}.inverse());
  const geom::Vec2 a = odo_from_nav.transform({3.2, -1});
  EXPECT_NEAR(s.current_sensor_map->segments[0].x0, a.x(), 1e-12);
  EXPECT_NEAR(s.current_sensor_map->segments[0].y0, a.y(), 1e-12);
  EXPECT_NEAR(s.current_sensor_map->robot_pose.x, 1.0, 1e-12);
  EXPECT_NEAR(s.current_sensor_map->robot_pose.theta, 0.0, 1e-12);
  ASSERT_TRUE(s.agm_tactical_frame);
  EXPECT_NEAR(s.agm_tactical_frame->theta, -0.1, 1e-12);
  // Frames that agree (no scan matching): nothing moved.
  SnapshotCollector same;
  same.add(record(channels::ODOMETRY, odom(1'000'000, 1, 0, 0)));
  same.add(record(channels::ODOMETRY, odom(2'000'000, 1, 0, 0)));
  csm.robot_pose = {1.0, 0.0, 0.0};
  same.add(record(channels::CURRENT_SENSOR_MAP, csm));
  EXPECT_EQ(same.at(1'600'000).current_sensor_map->segments[0].x0, 3.2);
}

TEST(SnapshotCollector, TruthInterpolatedAndOdometryFromTrue) {
  SnapshotCollector c;
  sim_state_t a{}, b{};
  a.utime = 1'000'000;
  b.utime = 2'000'000;
  a.robot_pose.x = 2;
  b.robot_pose.x = 4;
  mover_state_t m{};
  m.x = 0;
  m.radius = 0.25;
  a.movers.push_back(m);
  m.x = 1;
  b.movers.push_back(m);
  setLengths(a);
  setLengths(b);
  c.add(record(channels::SIM_STATE, a));
  c.add(record(channels::SIM_STATE, b));
  // Odometry has drifted: it thinks the robot is 1 m further in y and turned by 90 degrees.
  c.add(record(channels::ODOMETRY, odom(1'000'000, 2, 1, geom::kPi / 2)));
  c.add(record(channels::ODOMETRY, odom(2'000'000, 4, 1, geom::kPi / 2)));
  const auto s = c.at(1'500'000);
  ASSERT_TRUE(s.true_robot);
  EXPECT_NEAR(s.true_robot->x, 3.0, 1e-12);
  ASSERT_EQ(s.movers.size(), 1u);
  EXPECT_NEAR(s.movers[0].position.x(), 0.5, 1e-12);
  const auto T = s.odomFromTrue();
  ASSERT_TRUE(T);
  // The true robot position maps onto the odometry's.
  const auto p = T->transform(s.true_robot->position());
  EXPECT_NEAR(p.x(), s.robot->x, 1e-9);
  EXPECT_NEAR(p.y(), s.robot->y, 1e-9);
  // A point 1 m ahead of the true robot is 1 m ahead of the odometry robot (along +y).
  const auto q = T->transform(s.true_robot->transform({1, 0}));
  EXPECT_NEAR(q.x(), 3.0, 1e-9);
  EXPECT_NEAR(q.y(), 2.0, 1e-9);
}

TEST(ScanLog, SpanChannelsAndUndecodable) {
  const lasonic::fixture::ScratchDir scratch;
  const std::string path = scratch.file("lasonic_test_render_scan.lcmlog");
  {
    LogWriter w(path);
    auto o = odom(5'000'000, 0, 0, 0);
    w.write(channels::ODOMETRY, 1, o);
    auto rm = lines(2'000'000, {{0, 0, 1, 0}});
    w.write(channels::RADAR_MAP, 2, rm);
    auto late = odom(9'000'000, 0, 0, 0);
    w.write(channels::ODOMETRY, 3, late);
    w.writeRaw(channels::SECTOR_MAP, 4, {9, 9, 9});
    w.writeRaw("LCM_SELF_TEST", 5, {1});
  }
  const auto info = scanLog(path);
  EXPECT_EQ(info.events, 5);
  EXPECT_EQ(info.start_utime, 2'000'000);
  EXPECT_EQ(info.end_utime, 9'000'000);
  EXPECT_DOUBLE_EQ(info.durationS(), 7.0);
  EXPECT_EQ(info.messages.at(channels::ODOMETRY), 2);
  EXPECT_TRUE(info.has(channels::RADAR_MAP));
  EXPECT_FALSE(info.has(channels::SECTOR_MAP));
  EXPECT_EQ(info.undecodable.at(channels::SECTOR_MAP), 1);
  EXPECT_THROW(scanLog("/nonexistent/x.lcmlog"), LogError);
}

// The moment of the most sonar sectors (lasonic-render --most-sonar): sonar, copied and remembered
// sectors count, laser ones do not; equals go to the earliest; none without a SECTOR_MAP.
TEST(ScanLog, MostSonarSectors) {
  const auto sectors = [](int64_t t, std::vector<int8_t> src) {
    sector_map_t m{};
    m.utime = t;
    m.robot_radius = 0.35f;
    m.max_range = 3.0f;
    m.nsectors = static_cast<int32_t>(src.size());
    m.distance.assign(src.size(), 1.0f);
    m.source = std::move(src);
    m.laser_distance.assign(m.source.size(), -1.0f);
    m.sonar_distance.assign(m.source.size(), -1.0f);
    m.remembered_distance.assign(m.source.size(), -1.0f);
    setLengths(m);
    return m;
  };
  const int8_t L = sector_map_t::SOURCE_LASER, S = sector_map_t::SOURCE_SONAR,
               C = sector_map_t::SOURCE_SONAR_COPIED, R = sector_map_t::SOURCE_REMEMBERED,
               N = sector_map_t::SOURCE_NONE;
  const lasonic::fixture::ScratchDir scratch;
  const std::string path = scratch.file("lasonic_test_render_most_sonar.lcmlog");
  {
    LogWriter w(path);
    auto a = sectors(1'000'000, {L, L, L, L, S, N});  // 1
    w.write(channels::SECTOR_MAP, 1, a);
    auto b = sectors(2'000'000, {S, C, R, L, L, L});  // 3
    w.write(channels::SECTOR_MAP, 2, b);
    auto c = sectors(3'000'000, {L, L, L, L, L, L});  // 0, though all sectors are known
    w.write(channels::SECTOR_MAP, 3, c);
    auto d = sectors(4'000'000, {R, R, C, N, N, N});  // 3 again: later, so not chosen
    w.write(channels::SECTOR_MAP, 4, d);
    w.writeRaw(channels::SECTOR_MAP, 5, {9, 9, 9});  // undecodable: not a moment
  }
  auto info = scanLog(path);
  EXPECT_EQ(info.most_sonar_sectors, 3);
  EXPECT_EQ(info.most_sonar_utime, 2'000'000);
  {
    LogWriter w(path);  // written out of order: the earlier of equals still wins
    auto d = sectors(4'000'000, {R, R, C, N, N, N});
    w.write(channels::SECTOR_MAP, 1, d);
    auto b = sectors(2'000'000, {S, C, R, L, L, L});
    w.write(channels::SECTOR_MAP, 2, b);
  }
  info = scanLog(path);
  EXPECT_EQ(info.most_sonar_utime, 2'000'000);
  {
    LogWriter w(path);
    auto o = odom(5'000'000, 0, 0, 0);
    w.write(channels::ODOMETRY, 1, o);
  }
  info = scanLog(path);
  EXPECT_EQ(info.most_sonar_sectors, -1);
}

// ------------------------------------------------------------------------------ drawing

TEST(Fig8, LayoutAndOptions) {
  RenderOptions o;
  const auto s = fig8Size(o);
  EXPECT_EQ(s.width, 4 * o.panel_px);
  const auto v = panelView(5, {10, 20}, o);  // second row, second column
  EXPECT_DOUBLE_EQ(v.x0, o.panel_px);
  const auto c = v.toPixel({10, 20});
  EXPECT_DOUBLE_EQ(c.x(), v.x0 + o.panel_px / 2.0);
  EXPECT_DOUBLE_EQ(c.y(), v.y0 + o.panel_px / 2.0);
  EXPECT_LT(v.toPixel({10, 21}).y(), c.y());  // y up
  o.view_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(checkOptions(o), RenderError);
  o.view_m = 7;
  o.panel_px = 10;
  EXPECT_THROW(checkOptions(o), RenderError);
}

TEST(Fig8, MissingChannelsAreNamed) {
  Snapshot s;
  s.utime = 1'000'000;
  s.robot = geom::Pose2{0, 0, 0};
  s.in_log = {channels::RADAR_MAP};  // in the log, but not yet at this moment
  std::vector<PanelStatus> st;
  draw(s, st);
  ASSERT_EQ(st.size(), static_cast<size_t>(kPanels));
  EXPECT_FALSE(panel(st, "a").drawn);
  EXPECT_EQ(panel(st, "a").note, "no RADAR_MAP yet at this time");
  EXPECT_EQ(panel(st, "e'").note, "no AGM_TACTICAL in log");
  EXPECT_EQ(panel(st, "f").note, "no CURRENT_SENSOR_MAP in log");
  EXPECT_EQ(panel(st, "g").note, "no SECTOR_MAP in log");
}

TEST(Fig8, OccupiedAgmCellWhereItIs) {
  Snapshot s;
  s.utime = 1'000'000;
  s.robot = geom::Pose2{5, 5, 0};
  auto g = grid(1'000'000, 0, 0, 0.1, 100, 100);
  // Cell (60, 50): x in [6.0, 6.1), y in [5.0, 5.1): 1 m right of the robot.
  const size_t occ = 50 * 100 + 60, weak = 50 * 100 + 40;
  g.g[occ] = 3;
  g.gp[occ] = 5;
  g.g[weak] = 1;
  g.gp[weak] = 1;  // below the threshold: light
  s.agm_tactical = g;
  s.agm_lines = lines(1'000'000, {{4.0, 6.5, 6.0, 6.5}}, line_segment_t::SOURCE_SONAR);
  s.in_log = {channels::AGM_TACTICAL, channels::AGM_LINES};
  std::vector<PanelStatus> st;
  const auto im = draw(s, st);
  const auto& p = panel(st, "e'");
  EXPECT_TRUE(p.drawn) << p.note;
  EXPECT_NE(p.note.find("1 in view with Gp >= 2"), std::string::npos) << p.note;
  EXPECT_NE(p.note.find("1 AGM_LINES"), std::string::npos) << p.note;
  const auto v = panelView(5, {5, 5}, {});
  const auto c = v.toPixel({6.05, 5.05});
  EXPECT_GT(im.r(c.x(), c.y()), 100);  // dark orange-brown
  EXPECT_LT(im.g(c.x(), c.y()), 90);
  EXPECT_LT(im.b(c.x(), c.y()), 40);
  const auto w = v.toPixel({4.05, 5.05});
  EXPECT_GT(im.g(w.x(), w.y()), 150);  // light orange
  EXPECT_LT(im.b(w.x(), w.y()), 200);
  const auto l = v.toPixel({5.0, 6.5});  // on the sonar line
  EXPECT_GT(im.r(l.x(), l.y()), 180);
  EXPECT_LT(im.b(l.x(), l.y()), 60);
  // The same cell in the operational panel's place stays white: that panel has no map.
  const auto e = panelView(4, {5, 5}, {}).toPixel({6.05, 5.05});
  EXPECT_EQ(im.at(e.x(), e.y()), 0xffffffu);
}

// A tactical cell only echoes the laser could not check made (the pilot does not remember it) has
// its own colour and count; a checked one, and one of a map without the record, the usual.
TEST(Fig8, CellsOnlyUncheckedEchoesMadeStandApart) {
  Snapshot s;
  s.utime = 1'000'000;
  s.robot = geom::Pose2{5, 5, 0};
  auto g = grid(1'000'000, 0, 0, 0.1, 100, 100);
  const size_t unchecked = 50 * 100 + 60, both = 50 * 100 + 40;  // 1 m right, 1 m left
  for (size_t i : {unchecked, both}) {
    g.g[i] = 3;
    g.gp[i] = 5;
  }
  g.heard.assign(g.g.size(), int8_t{grid_map_t::HEARD_UNKNOWN});
  g.heard[unchecked] = grid_map_t::HEARD_UNCHECKED;
  g.heard[both] = grid_map_t::HEARD_BOTH;
  s.agm_tactical = g;
  s.in_log = {channels::AGM_TACTICAL};
  std::vector<PanelStatus> st;
  auto im = draw(s, st);
  const auto v = panelView(5, {5, 5}, {});
  const auto u = v.toPixel({6.05, 5.05}), b = v.toPixel({4.05, 5.05});
  EXPECT_NE(panel(st, "e'").note.find("2 in view with Gp >= 2 (1 only echoes the laser could not check made)"),
            std::string::npos)
      << panel(st, "e'").note;
  EXPECT_GT(im.b(u.x(), u.y()), 130);  // grey-violet
  EXPECT_LT(im.b(b.x(), b.y()), 40);   // dark orange-brown: the laser checked some of its echoes
  s.agm_tactical->heard[both] = grid_map_t::HEARD_UNCHECKED;
  s.agm_tactical->heard.pop_back();  // no record for every cell: no cell stands apart
  im = draw(s, st);
  EXPECT_EQ(panel(st, "e'").note.find("could not check"), std::string::npos) << panel(st, "e'").note;
  EXPECT_LT(im.b(u.x(), u.y()), 40);
}

TEST(Fig8, InvalidGridSaysSo) {
  Snapshot s;
  s.utime = 1;
  s.robot = geom::Pose2{0, 0, 0};
  auto g = grid(1, 0, 0, 0.1, 10, 10);
  g.width = 11;  // ncells no longer width*height
  s.agm_operational = g;
  auto g2 = grid(1, 0, 0, std::numeric_limits<double>::quiet_NaN(), 10, 10);
  s.agm_tactical = g2;
  std::vector<PanelStatus> st;
  draw(s, st);
  EXPECT_FALSE(panel(st, "e").drawn);
  EXPECT_NE(panel(st, "e").note.find("invalid AGM_OPERATIONAL message: ncells 100 != width*height"), std::string::npos);
  EXPECT_NE(panel(st, "e'").note.find("cell_size"), std::string::npos);
}

TEST(Fig8, SectorMapColouredBySourceInTheRobotFrame) {
  Snapshot s;
  s.utime = 1;
  s.robot = geom::Pose2{0, 0, geom::kPi / 2};  // facing +y
  sector_map_t m{};
  m.utime = 1;
  m.robot_pose.theta = geom::kPi / 2;
  m.robot_radius = 0.35f;
  m.max_range = 3.0f;
  m.nsectors = 48;
  m.distance.assign(48, -1.0f);
  m.source.assign(48, static_cast<int8_t>(sector_map_t::SOURCE_NONE));  // a copy: the constant has no definition to bind to
  m.laser_distance.assign(48, -1.0f);
  m.sonar_distance.assign(48, -1.0f);
  m.distance[24] = 1.0f;  // straight ahead: laser
  m.source[24] = sector_map_t::SOURCE_LASER;
  m.distance[36] = 1.0f;  // 90 deg left: sonar
  m.source[36] = sector_map_t::SOURCE_SONAR;
  m.sonar_stale = 1;
  m.sonar_age_s = 0.8f;
  setLengths(m);
  s.sector_map = m;
  std::vector<PanelStatus> st;
  const auto im = draw(s, st);
  const auto& p = panel(st, "g");
  EXPECT_TRUE(p.drawn);
  EXPECT_EQ(p.note, "1 laser, 1 sonar, 0 copied, 0 remembered of 48 sectors");
  const auto v = panelView(7, {0, 0}, {});
  // Sector 24 spans bearings [0, 7.5 deg) from straight ahead (+y); 0.35 + 0.5 m out.
  const double a = geom::kPi / 2 + geom::deg2rad(3.75);
  const auto ahead = v.toPixel({0.85 * std::cos(a), 0.85 * std::sin(a)});
  EXPECT_GT(im.b(ahead.x(), ahead.y()), im.r(ahead.x(), ahead.y()) + 40);  // blue: laser
  const double l = geom::kPi + geom::deg2rad(3.75);                          // robot's left = -x
  const auto left = v.toPixel({0.85 * std::cos(l), 0.85 * std::sin(l)});
  EXPECT_GT(im.r(left.x(), left.y()), im.b(left.x(), left.y()) + 80);  // orange: sonar
  // Behind the robot: nothing reported.
  const auto back = v.toPixel({0, -0.85});
  EXPECT_EQ(im.at(back.x(), back.y()), 0xffffffu);
}

TEST(Fig8, TruthPlacedInTheOdometryFrame) {
  auto sc = sim::parseScenario(Config::fromString(R"(
name: t
duration_s: 1
seed: 1
obstacles:
  - {shape: segment, material: wall, from: [2, -2], to: [2, 2]}
robot: {radius: 0.35, path: [[0,0],[1,0]], speed: 0.1}
)"));
  Snapshot s;
  s.utime = 1;
  s.true_robot = geom::Pose2{0, 0, 0};
  s.robot = geom::Pose2{0, 0, geom::kPi / 2};  // odometry: turned by 90 deg
  std::vector<PanelStatus> st;
  const auto im = draw(s, st, &sc);
  // The wall 2 m ahead of the true robot is 2 m ahead of the odometry robot: along y = 2.
  const auto v = panelView(0, {0, 0}, {});
  const auto on = v.toPixel({0.5, 2.0});
  EXPECT_LT(im.at(on.x(), on.y()), 0xf0f0f0u);
  const auto off = v.toPixel({2.0, 0.5});
  EXPECT_EQ(im.at(off.x(), off.y()), 0xffffffu);
}

TEST(Fig8, BadNumbersDoNotBreakTheDrawing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  Snapshot s;
  s.utime = 1;
  s.robot = geom::Pose2{nan, 0, 0};
  s.radar_map = lines(1, {{nan, 0, 1, 0}, {0, 0, inf, 0}, {1e300, 0, -1e300, 0}, {0, 0, 1, 1}});
  SonarBeam b;
  b.pose = {0, 0, nan};
  b.beam_width = 0.5;
  b.range = 1;
  s.sonar = {b};
  b.pose = {0, 0, 0};
  b.range = -5;
  s.hypothesis = {b};
  b.range = 1e30;
  b.cls = complement_reading_t::CLASS_COMPLEMENTARY;
  s.complement = {b};
  sector_map_t m{};
  m.nsectors = 4;
  m.distance = {static_cast<float>(nan), -1.0f, static_cast<float>(inf), 1e30f};
  m.source = {1, 2, 3, 99};
  m.laser_distance = m.distance;
  m.sonar_distance = m.distance;
  m.robot_radius = nan;
  setLengths(m);
  s.sector_map = m;
  std::vector<PanelStatus> st;
  EXPECT_NO_THROW(draw(s, st));
  EXPECT_TRUE(panel(st, "a").drawn);
  EXPECT_NE(panel(st, "a").note.find("1 segments"), std::string::npos) << panel(st, "a").note;
  EXPECT_NE(panel(st, "a").note.find("3 invalid skipped"), std::string::npos) << panel(st, "a").note;
}

TEST(Fig8, PngWrittenAndReadBack) {
  const lasonic::fixture::ScratchDir scratch;
  const std::string path = scratch.file("lasonic_test_render.png");
  Snapshot s;
  s.utime = 1;
  s.robot = geom::Pose2{0, 0, 0};
  s.radar_map = lines(1, {{-1, 1, 1, 1}});
  RenderOptions o;
  o.panel_px = 300;
  writeFig8Png(path, s, nullptr, o);
  cairo_surface_t* png = cairo_image_surface_create_from_png(path.c_str());
  ASSERT_EQ(cairo_surface_status(png), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(png), fig8Size(o).width);
  EXPECT_EQ(cairo_image_surface_get_height(png), fig8Size(o).height);
  cairo_surface_destroy(png);
  EXPECT_THROW(writeFig8Png("/nonexistent-dir/x.png", s, nullptr, o), RenderError);
}
