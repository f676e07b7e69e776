// lasonic-render-check: helpers for tests/integration/render.sh.
//
//   lasonic-render-check png FILE WIDTH HEIGHT
//       Reads FILE back with Cairo; fails (exit 1) unless it is a WIDTH x HEIGHT PNG that is not
//       blank. Prints "width W height H nonwhite F colours N" (F: fraction of pixels that are not
//       white; N: distinct colours, capped at 10000).
//   lasonic-render-check corrupt IN OUT
//       Copies the log IN to OUT and appends, at IN's last message time, events a renderer must
//       survive: random bytes and a truncated message on every drawn channel, a message with
//       time 0, an AGM_OPERATIONAL whose ncells is not width*height, a RADAR_MAP with NaN and
//       huge coordinates, a SECTOR_MAP with NaN / infinite distances and an unknown source.
#include <cairo.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <string>

#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"

#include <lasonic/grid_map_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sector_map_t.hpp>

using namespace lasonic;

namespace {

int checkPng(const std::string& path, int want_w, int want_h) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(path.c_str());
  if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
    std::fprintf(stderr, "%s: not a readable PNG: %s\n", path.c_str(), cairo_status_to_string(cairo_surface_status(s)));
    cairo_surface_destroy(s);
    return 1;
  }
  const int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
  const int stride = cairo_image_surface_get_stride(s);
  const unsigned char* data = cairo_image_surface_get_data(s);
  int64_t nonwhite = 0;
  std::set<uint32_t> colours;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint32_t px = *reinterpret_cast<const uint32_t*>(data + y * stride + 4 * x) & 0xffffff;
      if (px != 0xffffff) ++nonwhite;
      if (colours.size() < 10000) colours.insert(px);
    }
  cairo_surface_destroy(s);
  const double frac = w * h > 0 ? static_cast<double>(nonwhite) / (static_cast<double>(w) * h) : 0;
  std::printf("width %d height %d nonwhite %.4f colours %zu\n", w, h, frac, colours.size());
  if (w != want_w || h != want_h) {
    std::fprintf(stderr, "%s: %d x %d px, expected %d x %d\n", path.c_str(), w, h, want_w, want_h);
    return 1;
  }
  // A picture with panels, text and data has well over 1 % ink and many colours.
  if (frac < 0.01 || colours.size() < 20) {
    std::fprintf(stderr, "%s: looks blank (%.4f non-white, %zu colours)\n", path.c_str(), frac, colours.size());
    return 1;
  }
  return 0;
}

int corrupt(const std::string& in, const std::string& out) {
  LogWriter w(out);
  int64_t last = 0, ts = 0;
  {
    LogReader r(in);
    while (auto e = r.next()) {
      w.writeRaw(e->channel, e->timestamp, e->data);
      ts = e->timestamp;
      if (e->channel == channels::ODOMETRY)
        if (auto o = decodeAs<odometry_t>(e->data)) last = std::max(last, o->utime);
    }
  }
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> byte(0, 255);
  const char* drawn[] = {channels::RADAR_MAP, channels::SONAR_HYPOTHESIS, channels::SONAR_RING,
                         channels::SONAR_COMPLEMENT, channels::AGM_OPERATIONAL, channels::AGM_TACTICAL,
                         channels::AGM_LINES, channels::CURRENT_SENSOR_MAP, channels::SECTOR_MAP,
                         channels::ODOMETRY, channels::SIM_STATE};
  for (const char* ch : drawn) {
    std::vector<uint8_t> junk(64);
    for (auto& b : junk) b = static_cast<uint8_t>(byte(rng));
    w.writeRaw(ch, ts, junk);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Truncated and timeless: a valid map cut short, an odometry message at time 0.
  line_map_t rm{};
  rm.utime = last;
  rm.segments.resize(3);
  rm.segments[0].x0 = nan;
  rm.segments[1].x1 = 1e300;
  rm.segments[2].x0 = rm.segments[2].y0 = 0;
  rm.segments[2].x1 = rm.segments[2].y1 = 0.5;
  auto bytes = encodeMsg(rm);
  w.writeRaw(channels::RADAR_MAP, ts, std::vector<uint8_t>(bytes.begin(), bytes.end() - 5));
  w.write(channels::RADAR_MAP, ts, rm);
  odometry_t o{};
  o.utime = 0;
  w.write(channels::ODOMETRY, ts, o);
  grid_map_t g{};
  g.utime = last;
  g.width = 7;
  g.height = 7;
  g.cell_size = 0.1f;
  g.g.assign(10, 1);
  g.h.assign(10, 0);
  g.gp.assign(10, 5);
  g.heard.assign(10, 0);
  // setLengths refuses this (ncells 10 != 49), so encode it by hand: what a foreign or broken
  // publisher could send.
  g.ncells = 10;
  std::vector<uint8_t> gbuf(static_cast<size_t>(g.getEncodedSize()));
  if (g.encode(gbuf.data(), 0, static_cast<int>(gbuf.size())) < 0) throw std::runtime_error("encode failed");
  w.writeRaw(channels::AGM_OPERATIONAL, ts, gbuf);
  sector_map_t m{};
  m.utime = last;
  m.nsectors = 3;
  m.distance = {static_cast<float>(nan), std::numeric_limits<float>::infinity(), 0.5f};
  m.source = {1, 2, 77};
  m.laser_distance = m.distance;
  m.sonar_distance = m.distance;
  m.robot_radius = -1;
  m.robot_pose.x = nan;
  w.write(channels::SECTOR_MAP, ts, m);
  std::printf("appended bad events at message time %lld\n", static_cast<long long>(last));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string cmd = argc > 1 ? argv[1] : "";
  try {
    if (cmd == "png" && argc == 5) return checkPng(argv[2], std::stoi(argv[3]), std::stoi(argv[4]));
    if (cmd == "corrupt" && argc == 4) return corrupt(argv[2], argv[3]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lasonic-render-check: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr, "usage: lasonic-render-check png FILE WIDTH HEIGHT | corrupt IN OUT\n");
  return 2;
}
