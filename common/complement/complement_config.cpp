#include "complement/complement_config.hpp"

#include <cmath>

namespace lasonic::complement {

ComplementConfig complementConfig(const Config& c) {
  c.allowOnly({"tolerance", "beam_width_deg", "range_limit", "rm_max_age_s", "rm_max_age_scans", "radar_map", "outside_laser_view", "poles",
               "crosstalk", "late_echoes", "late_echo_window_s", "radar_map_memory"});
  ComplementConfig cfg;
  ComplementParams& p = cfg.params;
  p.tolerance = c.get("tolerance", p.tolerance, Range::nonNegative());
  p.model.beam_width = geom::deg2rad(
      c.get("beam_width_deg", geom::rad2deg(p.model.beam_width), Range{0.0, 179.0, true}));
  p.model.range_limit = c.get("range_limit", p.model.range_limit, Range::positive());
  // (A tolerance as wide as the range limit makes every echo agree with the laser: no complement.)
  if (!(p.tolerance < p.model.range_limit))
    c.fail("tolerance", std::to_string(p.tolerance) + " m is not below range_limit (" +
                            std::to_string(p.model.range_limit) + " m): every echo would be redundant");
  p.max_rm_age_us = std::llround(
      1e6 * c.get("rm_max_age_s", static_cast<double>(p.max_rm_age_us) * 1e-6, Range::positiveDuration()));
  cfg.rm_max_age_scans = c.get("rm_max_age_scans", cfg.rm_max_age_scans, Range::between(0, 100));

  p.outside_view_complementary = c.getChoice("outside_laser_view", p.outside_view_complementary,
                                              {{"complementary", true}, {"paper", false}});
  p.crosstalk_corners = c.getChoice("crosstalk", p.crosstalk_corners, {{"corners", true}, {"paper", false}});
  p.late_echoes = c.getChoice("late_echoes", p.late_echoes, {{"laser_map", true}, {"paper", false}});
  p.late_echo_window_us = std::llround(
      1e6 * c.get("late_echo_window_s", static_cast<double>(p.late_echo_window_us) * 1e-6, Range::positiveDuration()));

  const Config mc = c.section("radar_map_memory");
  mc.allowOnly({"memory_s", "max_incidence_deg", "min_length_m"});
  cfg.radar_map_memory_min_length = mc.get("min_length_m", cfg.radar_map_memory_min_length, Range::nonNegative());
  cfg.radar_map_memory_s = mc.get("memory_s", cfg.radar_map_memory_s, Range::duration());
  cfg.radar_map_memory_max_incidence = geom::deg2rad(
      mc.get("max_incidence_deg", geom::rad2deg(cfg.radar_map_memory_max_incidence), Range{0.0, 90.0, true}));
  cfg.radar_map = radarMapConfig(c.section("radar_map"));
  RadarMapConfig& r = cfg.radar_map;

  const Config pc = c.section("poles");
  pc.allowOnly({"min_points", "match", "baseline", "memory_s", "keep_confirmed"});
  PoleConfig& po = cfg.poles;
  po.min_points = pc.get("min_points", po.min_points, Range::between(0, 1e6));
  po.match = pc.get("match", po.match, Range::nonNegative());
  po.baseline = pc.get("baseline", po.baseline, Range::nonNegative());
  po.memory_s = pc.get("memory_s", po.memory_s, Range::duration());
  po.keep_confirmed = pc.get("keep_confirmed", po.keep_confirmed);
  r.pole_min_points = po.min_points;
  return cfg;
}

RadarMapConfig radarMapConfig(const Config& rm) {
  rm.allowOnly({"jump_abs", "jump_rel", "split_threshold", "min_points", "min_length"});
  RadarMapConfig r;
  r.jump_abs = rm.get("jump_abs", r.jump_abs, Range::positive());
  r.jump_rel = rm.get("jump_rel", r.jump_rel, Range::nonNegative());
  r.split_threshold = rm.get("split_threshold", r.split_threshold, Range::positive());
  r.min_points = rm.get("min_points", r.min_points, Range{2, 1e6, false});
  r.min_length = rm.get("min_length", r.min_length, Range::nonNegative());
  return r;
}

}  // namespace lasonic::complement
