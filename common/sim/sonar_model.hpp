#pragma once
// The ideal sonar profile (README "Sensor models": the method's idealised sonar, the
// simulator's first model) as plain functions, so a test can fire one sensor at a hand-built
// world. The physical profile, the default, is sim/sonar_physical.hpp. SonarDriverCore
// (drivers.hpp) schedules the firings and wraps the readings into SONAR_RING / SONAR_TRUTH.
//
// One firing of one sensor (ideal profile):
//  1. rays_per_beam rays, evenly across the beam opening, edges included, are cast from the
//     sensor's true pose; sound passes through no material, so each ray stops at its first hit.
//  2. A hit echoes straight back if its incidence angle is within the material's
//     sonar_echo_angle and the material's echo_prob draw passes. That draw is made once per
//     reading and obstacle, not per ray: one glass pane is either heard or not.
//  3. The reading is the nearest direct echo over all rays (the first echo to arrive wins),
//     plus noise N(0, noise_std + noise_rel * range): cause DIRECT.
//  4. No direct echo: with multipath_prob the sound mirrors off the surfaces it met at oblique
//     incidence (beyond their echo angle), and each mirrored ray is followed through up to
//     multipath_bounces specular reflections (the first mirror included). At each surface met:
//     - within its echo angle (and its echo_prob draw passes): the echo is assumed to retrace
//       the path back to the sensor, so the reading is the one-way path d1 + d2 + ... + dk
//       (round trip / 2) if that is within range_max; if the draw fails, no echo on this ray;
//     - oblique again: the sound mirrors once more (if bounces are left, else no echo);
//     - after two or more reflections (a corner) the sound may instead come back to the
//       transducer itself, from any direction within its beam: when the ray's tube (the beam
//       slice it samples, beam_width / (rays_per_beam - 1) wide) covers the sensor with nothing
//       in between, the reading is half the closed loop's length.
//     SPECULAR_LONG (never shorter than the first mirror), nearest over the rays. Otherwise, or
//     beyond range_max: NO_ECHO. multipath_bounces = 1 is the single-mirror model.
//  5. Independently per reading, crosstalk (crosstalk_prob) or a foreign source (foreign_prob)
//     replaces the reading by a too-short one, uniform in [range_min, reading or range_max].
//
// Truth (sonar_cause_t): obstacle and laser_visible name the surface that echoed (DIRECT), the
// mirror (SPECULAR_LONG), or, for CROSSTALK/FOREIGN, those of the reading that was replaced;
// true_range is the noise-free range of the direct echo that occurred (also when crosstalk or a
// foreign source replaced it), -1 if there was none; nearest_laser_visible is the nearest
// laser-reflecting surface inside the ideal beam (ideal_beam_width, ideal_range), -1 if none.
#include <random>
#include <vector>

#include <lasonic/sonar_cause_t.hpp>

#include "core/physics.hpp"
#include "sim/drivers.hpp"

namespace lasonic::sim {

using lasonic::timeOfFlight;  // core/physics.hpp

// A regular ring (MOBOT-IV): sensor i at bearing offset + i*360°/count on a circle of `radius`,
// its axis pointing outward, in group i % groups (so 24 sensors in 6 groups fire 4 at a time,
// 90° apart, and neighbours never fire together).
std::vector<SonarSensor> ringSensors(int count, double radius, double beam_width, int groups,
                                     double offset = 0);

// Sensor ids of each firing group, ascending; groups are numbered 0..n-1.
std::vector<std::vector<int>> firingGroups(const std::vector<SonarSensor>& sensors);

// Mirror image of a direction off a surface with unit normal n.
inline geom::Vec2 mirror(const geom::Vec2& dir, const geom::Vec2& n) { return dir - 2.0 * dir.dot(n) * n; }

struct SonarReading {
  float range = 0;          // [m] meaningless when no_echo (set to range_max)
  bool no_echo = true;
  sonar_cause_t truth{};    // sensor_id left 0: the caller knows it
};

// One firing of a sensor at the true global pose `sensor`, against `world` (movers already set).
SonarReading fireSensor(const WorldGeometry& world, const geom::Pose2& sensor, double beam_width,
                        const SonarConfig& c, std::mt19937_64& rng);

// Distance from the sector's apex to the nearest laser-reflecting primitive inside it, -1 if none.
double nearestLaserVisible(const std::vector<Primitive>& prims, const geom::Sector& sector);

}  // namespace lasonic::sim
