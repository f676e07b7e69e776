#include "lcmio/lengths.hpp"

#include <stdexcept>
#include <string>

namespace lasonic {
namespace {
template <typename Count, typename V, typename... Vs>
Count sameSize(const char* type, const V& first, const Vs&... rest) {
  const size_t n = first.size();
  if (((rest.size() != n) || ...))
    throw std::logic_error(std::string(type) + ": parallel arrays differ in length");
  return static_cast<Count>(n);
}
}  // namespace

void setLengths(laser_scan_t& m) {
  m.nranges = sameSize<int32_t>("laser_scan_t", m.ranges, m.flags, m.offset_us);
}
void setLengths(sonar_ring_t& m) {
  m.nreadings = sameSize<int32_t>("sonar_ring_t", m.sensor_id, m.range, m.no_echo, m.mount, m.beam_width);
}
void setLengths(sonar_geometry_t& m) {
  m.num_sensors = sameSize<int32_t>("sonar_geometry_t", m.mount, m.beam_width, m.group_of);
}
void setLengths(line_map_t& m) { m.nsegments = sameSize<int32_t>("line_map_t", m.segments); }
void setLengths(hypothetical_scan_t& m) {
  m.nreadings = sameSize<int32_t>("hypothetical_scan_t", m.sensor_id, m.range, m.sensor_pose);
}
void setLengths(complement_t& m) { m.nreadings = sameSize<int32_t>("complement_t", m.readings); }
void setLengths(grid_map_t& m) {
  // A producer that does not record which echoes made its cells may leave `heard` empty: not
  // recorded anywhere (HEARD_UNKNOWN).
  if (m.heard.empty()) m.heard.assign(m.g.size(), int8_t{grid_map_t::HEARD_UNKNOWN});
  m.ncells = sameSize<int32_t>("grid_map_t", m.g, m.h, m.gp, m.heard);
  if (static_cast<int64_t>(m.width) * m.height != m.ncells)
    throw std::logic_error("grid_map_t: width*height != number of cells");
}
void setLengths(sector_map_t& m) {
  // A producer without a remembered source may leave it empty: nothing remembered anywhere.
  if (m.remembered_distance.empty()) m.remembered_distance.assign(m.distance.size(), -1.0f);
  m.nsectors = sameSize<int32_t>("sector_map_t", m.distance, m.source, m.laser_distance, m.sonar_distance,
                                 m.remembered_distance);
}
void setLengths(process_status_t& m) {
  m.nchannels = sameSize<int32_t>("process_status_t", m.channels);
  m.ncounters = sameSize<int32_t>("process_status_t", m.counter_names, m.counter_values);
}
void setLengths(sim_state_t& m) { m.nmovers = sameSize<int32_t>("sim_state_t", m.movers); }
void setLengths(sonar_truth_t& m) { m.nreadings = sameSize<int32_t>("sonar_truth_t", m.causes); }

namespace detail {
namespace {
int64_t bigEndian(const uint8_t* p, int bytes) {
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return bytes == 4 ? static_cast<int64_t>(static_cast<int32_t>(static_cast<uint32_t>(v))) : static_cast<int64_t>(v);
}
}  // namespace

WireCheck checkWire(const void* data, size_t size, int64_t hash, const WireShape& shape, int64_t cap) {
  const auto* p = static_cast<const uint8_t*>(data);
  WireCheck c;
  if (size < 8 || bigEndian(p, 8) != hash) {
    c.result = WireCheck::NotThisType;
    return c;
  }
  if (static_cast<int64_t>(size) < shape.fixed) {
    c.result = WireCheck::Truncated;
    return c;
  }
  c.claimed = bigEndian(p + shape.count_offset, 4);
  if (c.claimed < 0)
    c.result = WireCheck::Truncated;
  else if (c.claimed > cap)
    c.result = WireCheck::TooMany;
  else if (shape.fixed + c.claimed * shape.per_element > static_cast<int64_t>(size))
    c.result = WireCheck::Truncated;
  return c;
}
}  // namespace detail

void setLengths(laser_truth_t& m) { m.nranges = sameSize<int32_t>("laser_truth_t", m.obstacle); }

}  // namespace lasonic
