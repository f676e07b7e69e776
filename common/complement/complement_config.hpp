#pragma once
// The `complement:` section of the configuration (deploy/config/lasonic.yaml):
//
//   complement:
//     tolerance: 0.10        # [m] |r - h| <= tolerance: redundant
//     beam_width_deg: 30     # ideal beam opening (paper: 30)
//     range_limit: 2.20      # [m] hypothetical range limit (paper: 2.20)
//     rm_max_age_s: 0.5      # [s] an older Radar Map is stale: readings unverifiable
//     rm_max_age_scans: 2.5  # the same in the laser's own scan periods where longer (at most 4 s)
//     radar_map: {jump_abs: 0.10, jump_rel: 0.05, split_threshold: 0.05, min_points: 6, min_length: 0.15}
//     poles: {min_points: 1, match: 0.03, baseline: 0.10, memory_s: 2.0}  # 0 points: none (the paper)
//     radar_map_memory: {memory_s: 3.0, max_incidence_deg: 10, min_length_m: 0}  # earlier scans'
//                            # lines where the newest does not look (memory_s 0: the paper)
//
// Every key is optional (the defaults above); unknown keys and out-of-range values are
// ConfigErrors that name the key path.
#include "complement/complement.hpp"
#include "complement/pole_tracker.hpp"
#include "complement/radar_map.hpp"
#include "complement/radar_map_memory.hpp"
#include "core/config.hpp"

namespace lasonic::complement {

struct ComplementConfig {
  RadarMapConfig radar_map;
  PoleConfig poles;
  ComplementParams params;
  // RadarMapMemory (complement/radar_map_memory.hpp): how long a scan's lines are kept for where
  // later scans do not look (0: off, the paper: the newest scan's lines only), and the lines
  // seen only within max_incidence [rad] of their normal (a glass pane's glint) that are not.
  double radar_map_memory_s = 30.0;
  double radar_map_memory_max_incidence = geom::deg2rad(10.0);
  double radar_map_memory_min_length = 0.0;  // [m] shorter lines are not kept
  // params.max_rm_age_us in the laser's own scan periods (ScanPeriod, timed from its scans) where
  // that is longer, at most kMaxRmAgeS; 0: params.max_rm_age_us always.
  double rm_max_age_scans = 2.5;
  static constexpr double kMaxRmAgeS = 4.0;
};

ComplementConfig complementConfig(const Config& section);  // throws ConfigError
// The laser's cut into clusters and segments, `complement.radar_map` alone (pole_min_points
// left at its default). The pilot and the navigator cut LASER_SCAN too (dark continuation, scan
// matching, glints) and read the same keys: one laser, one rule. Throws ConfigError.
RadarMapConfig radarMapConfig(const Config& radar_map_section);

}  // namespace lasonic::complement
