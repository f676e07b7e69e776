#pragma once
// LCM 1.3.1 does not check array length fields on encode: a wrong count silently writes
// garbage. Every message with arrays is finalised here, in one place, from the vectors' sizes,
// and parallel arrays are checked to agree (a programming error -> std::logic_error).
// Node::publish and LogWriter::write call setLengths() for every message.
#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/laser_truth_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/process_status_t.hpp>
#include <lasonic/sector_map_t.hpp>
#include <lasonic/sim_state_t.hpp>
#include <lasonic/sonar_geometry_t.hpp>
#include <lasonic/sonar_ring_t.hpp>
#include <lasonic/sonar_truth_t.hpp>

namespace lasonic {

void setLengths(laser_scan_t& m);
void setLengths(sonar_ring_t& m);
void setLengths(sonar_geometry_t& m);
void setLengths(line_map_t& m);
void setLengths(hypothetical_scan_t& m);
void setLengths(complement_t& m);
void setLengths(grid_map_t& m);
void setLengths(sector_map_t& m);
void setLengths(process_status_t& m);
void setLengths(sim_state_t& m);
void setLengths(sonar_truth_t& m);
void setLengths(laser_truth_t& m);
// Types without arrays.
template <typename T> void setLengths(T&) {}

}  // namespace lasonic
