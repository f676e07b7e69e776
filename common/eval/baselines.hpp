#pragma once
// Baseline mappers scored on the same log as lasonic (README "Evaluation", baselines): each
// runs on the log's raw channels (ODOMETRY, LASER_SCAN, SONAR_RING; poses from ODOMETRY), is
// read out by the pilot's own SectorMap (same parameters) at the times of the pilot's
// SECTOR_MAP messages, and is scored against the same truth samples:
// - sonar_himm:   Borenstein & Koren's HIMM, sonar only (baselines/himm.hpp);
// - naive_fusion: every echo into the pilot's operational AGM, no complement extraction, plus
//                 the laser (baselines/naive_fusion.hpp);
// - log_odds:     an Elfes-style grid, cone model, laser and sonar, free space cleared, plus the
//                 laser points (baselines/log_odds.hpp).
// (laser_only, the laser part of the pilot's own maps, is scored by evalSectorMap.)
#include "baselines/himm.hpp"
#include "baselines/log_odds.hpp"
#include "baselines/naive_fusion.hpp"
#include "core/config.hpp"
#include "eval/evaluate.hpp"
#include "eval/observability.hpp"
#include "operational/sector_map.hpp"

namespace lasonic::eval {

struct BaselinesConfig {
  bool enabled = true;
  SectorMapParams readout;           // the pilot's sector map (pilot section)
  baselines::NaiveFusionParams naive_fusion;  // the pilot's AGM and placement (pilot section)
  baselines::HimmParams himm;
  baselines::LogOddsParams log_odds;
};
// Reads the `pilot:` and `baselines:` sections of a configuration file's root. Throws
// ConfigError naming the key path.
BaselinesConfig baselinesConfig(const Config& root);

// Writes baselines.<name>.sector_map.* for sonar_himm, naive_fusion and log_odds.
void evalBaselines(const RunLog& log, const SectorTruthTable& truth, const BaselinesConfig& cfg,
                   const EvalOptions& o, Metrics& m);

}  // namespace lasonic::eval
