#pragma once
// The simulated MOBOT-IV, as library classes. The live processes (lasonic-sim-world,
// lasonic-laser-driver, lasonic-sonar-driver) and the offline lasonic-sim are thin shells
// over these, so both produce the same statistics.
//
// Time: everything is driven by SIM_STATE (sim time). WorldCore produces SIM_STATE and
// ODOMETRY; the drivers consume SIM_STATE in time order and emit a measurement once the
// truth up to its time is known, interpolating the truth between consecutive states.
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include <lasonic/laser_scan_t.hpp>
#include <lasonic/laser_truth_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sim_state_t.hpp>
#include <lasonic/sonar_geometry_t.hpp>
#include <lasonic/sonar_ring_t.hpp>
#include <lasonic/sonar_truth_t.hpp>

#include "core/physics.hpp"
#include "sim/path_follower.hpp"
#include "sim/scenario.hpp"
#include "sim/world_geometry.hpp"

namespace lasonic::sim {

// Independent random stream per consumer, derived from the scenario seed.
uint64_t deriveSeed(uint64_t seed, const char* stream);

// ---------------------------------------------------------------- world + odometry
struct OdometryConfig {
  double rate_hz = 50;            // SIM_STATE rate (the truth the drivers interpolate), and ODOMETRY's
  double trans_noise = 0.01;      // [m/sqrt(m)] std-dev of distance error per sqrt(metre) driven
  double rot_noise = 0.005;       // [rad/sqrt(rad)] heading error per sqrt(radian) turned
  double drift_noise = 0.002;     // [rad/sqrt(m)] heading error per sqrt(metre) driven (wheel-base drift)
  // Systematic errors (UMBmark's: Borenstein & Feng 1996), 0 by default: they grow with what was
  // driven and turned, not with its square root, and no random walk model describes them.
  double scale_error = 0;         // distance read = true distance * (1 + scale_error) (wheel radius)
  double turn_scale_error = 0;    // heading change read = true * (1 + turn_scale_error) (wheel base)
  double curvature_error = 0;     // [rad/m] heading change read per metre driven (unequal wheels)
  // ODOMETRY's own rate, if lower (0: rate_hz): a base that reports every 100 ms (a Pioneer's
  // 10 Hz) while the truth stays fine-grained. The odometry still integrates every state.
  double publish_hz = 0;
};
OdometryConfig odometryConfig(const Config& c, OdometryConfig base = {});  // throws ConfigError
// Each key of an odometry section on its own (names, ranges), without the checks that depend on
// the layer beneath (publish_hz <= rate_hz): a scenario's override, when the scenario is loaded.
void checkOdometryKeys(const Config& c);

class WorldCore {
 public:
  // Sim time 0 is this utime, so that no message ever carries utime 0 ("unset").
  static constexpr int64_t kStartUtime = 1'000'000;

  // The odometry noise is drawn from deriveSeed(s.seed, "odometry").
  WorldCore(const Scenario& s, const OdometryConfig& c);
  WorldCore(const WorldCore&) = delete;
  WorldCore& operator=(const WorldCore&) = delete;
  // True state at utime (robot path following, movers); utime must not go backwards
  // (std::invalid_argument). Also advances the odometry to utime.
  sim_state_t stateAt(int64_t utime);
  // Odometry integrated (with drift) up to the last stateAt() call. Its frame starts equal to
  // the true start pose.
  odometry_t odometry() const;
  int64_t periodUs() const;
  // Whether the state at utime (one of startUtime() + k * periodUs()) publishes ODOMETRY: the
  // first state at or after each multiple of 1 / publish_hz.
  bool odometryDue(int64_t utime) const;
  int64_t startUtime() const { return kStartUtime; }
  bool finished(int64_t utime) const;  // past duration_s

 private:
  OdometryConfig cfg_;
  // A mover's place at sim time t: on its path at t - waited, plus where it stepped aside to.
  geom::Vec2 moverAt(size_t i, double t) const;
  // People keep out of the robot's way (MoverSpec::avoid_robot): wait, or step aside, never
  // into a static obstacle.
  void keepClear(size_t i, double t, double dt, const geom::Pose2& robot);
  // keepClear's choice of waiting, stepping aside or back towards the path; `before` is where
  // the mover stood at t - dt.
  void giveWay(size_t i, double t, double dt, const geom::Pose2& robot, const geom::Vec2& before);
  // True if a body of `radius` moving straight from `from` to `to` comes no nearer any static
  // obstacle than its radius (or, already that near, no nearer than it was).
  bool moveFree(const geom::Vec2& from, const geom::Vec2& to, double radius) const;

  Scenario scenario_;
  PathFollower robot_;
  std::vector<PathFollower> movers_;     // (their radii: scenario_.movers)
  // [s] how long a person waits for a robot in the way before walking round it: long enough
  // for a robot driving by to pass (its diameter at 0.3 m/s), not for ever at a standing one.
  static constexpr double kPatienceS = 2.0;
  // A person met head-on (the robot's centre within kHeadOnM of the line they walk, the robot
  // standing — below kStandingMps — or coming the other way within 45 deg: it fills their way)
  // steps back and aside, kSideStepRad (30 deg) off straight back: at 1 m/s they are round a
  // standing MOBOT-IV-sized robot in about 1.5 s, as from 0.2 m off the line.
  static constexpr double kHeadOnM = 0.1;
  static constexpr double kSideStepRad = 0.5;
  static constexpr double kStandingMps = 0.01;
  std::vector<double> waited_;           // [s] time each mover stood waiting for the robot
  std::vector<double> waiting_;          // [s] how long it has been waiting now
  std::vector<geom::Vec2> stepped_;      // [m] how far each mover stepped aside from its path
  int64_t end_utime_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> gauss_{0.0, 1.0};
  int32_t seq_ = 0;
  bool started_ = false;
  int64_t last_utime_ = 0;
  geom::Pose2 last_true_;
  odometry_t odom_{};
};

// ---------------------------------------------------------------- laser
// Sensor profiles (README "Sensor models"): physical (the default) models what a real scanner
// and transducer do; ideal is the method's idealised sensor (the simulator's first model), kept
// so that results can be compared.
enum class SensorProfile { Physical, Ideal };

struct LaserConfig {
  SensorProfile profile = SensorProfile::Physical;
  double scan_rate_hz = 5;        // scans per second (2 per revolution on MOBOT-IV)
  int readings = 720;             // per scan
  double fov_deg = 360;           // field of view, centred on the sensor's x axis
  double range_max = 15.0;        // [m]
  double range_min = 0.05;        // [m]
  double noise_std = 0.01;        // [m]
  geom::Pose2 mount{0, 0, 0};     // sensor pose in the robot frame
  // The direction the scanner turns, seen from above: a scanner mounted upside down turns
  // clockwise, and its LASER_SCAN says so by a negative angle_increment (README "Channels").
  bool clockwise = false;
  // --- physical profile
  // Detection limit: a surface of remission rho at incidence beta is seen up to
  // range_10pct * sqrt(rho cos(beta) / 0.1) (the returned power falls as 1/r²).
  double range_10pct = 5.0;       // [m] range at which a 10 % (dark grey) target is just detected
  double dropout_db = 1.5;        // [dB] width of the detection threshold (receiver noise)
  double beam_divergence = 0.6 * geom::kPi / 180;  // [rad] full angle of the beam
  double beam_diameter = 0.01;    // [m] at the exit window
  int footprint_rays = 5;         // sub-rays across the footprint (mixed pixels, thin objects)
  double merge_range = 0.5;       // [m] returns closer than this merge into one reading (pulse length)
  // [s] The scanner's host clock minus the odometry's: each LASER_SCAN (and its LASER_TRUTH)
  // is stamped this much later than it was taken. 0: one clock (README "Clocks").
  double clock_offset_s = 0;
};
LaserConfig laserConfig(const Config& c, LaserConfig base = {});
// As checkOdometryKeys, for a laser section (range_min < range_max is checked with its base).
void checkLaserKeys(const Config& c);

// A rotating scanner: a scan takes 1/scan_rate_hz; reading i is taken at angle
// angle_min + i*increment and at time utime + offset_us[i], evenly spread over the scan, and is
// cast against the truth interpolated to its own time. Scans follow each other back to back from
// the first SIM_STATE on.
class LaserDriverCore {
 public:
  // seed: the run's seed (normally the scenario's); the noise uses deriveSeed(seed, "laser").
  LaserDriverCore(const Scenario& s, const LaserConfig& c, uint64_t seed);
  struct Output {
    laser_scan_t scan;
    laser_truth_t truth;   // LASER_TRUTH: the obstacle that returned each reading
  };
  // Scans completed by the time of this state (usually 0 or 1). A state not after the previous
  // one, or with a non-finite pose, is refused with std::invalid_argument (nothing changes).
  std::vector<Output> onSimState(const sim_state_t& st);
  const LaserConfig& config() const { return cfg_; }

 private:
  Output makeScan(int64_t start_utime);
  // Truth at utime, interpolated between the buffered states that bracket it.
  void truthAt(int64_t utime, geom::Pose2& robot, std::vector<MoverPose>& movers) const;
  // One reading of the physical model: range (or < 0: no return) and the obstacle (-1: none or
  // a mixed pixel).
  std::pair<double, int> physicalReading(const geom::Vec2& origin, double angle);
  // Static primitives by the direction they lie in from the sensor during one scan (bins of
  // kBinWidth), so that a reading tests only those its footprint can meet.
  void binStatics(const geom::Vec2& from, double motion);
  static constexpr int kBins = 720;
  std::vector<std::vector<uint32_t>> bins_;

  std::unique_ptr<const Scenario> scenario_;  // heap: world_ points into it, cores stay movable
  WorldGeometry world_;
  LaserConfig cfg_;
  double angle_min_, angle_increment_;
  std::vector<int32_t> offset_us_;
  int64_t period_us_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> gauss_{0.0, 1.0};
  std::deque<sim_state_t> states_;
  int64_t next_scan_utime_ = 0;
  int32_t seq_ = 0;
};

// ---------------------------------------------------------------- sonar
// Beam model and config details: sim/sonar_model.hpp.
struct SonarSensor {
  geom::Pose2 mount;              // robot frame
  double beam_width = 0;          // [rad]
  int group = 0;
};
enum class CrosstalkModel { Geometric, Random };

struct SonarConfig {
  SensorProfile profile = SensorProfile::Physical;
  std::vector<SonarSensor> sensors;   // default: MOBOT-IV ring of 24, 15 deg apart, 6 groups of 4
  double range_max = 3.0;             // [m]
  double range_min = 0.10;            // [m] transducer ringing hides nearer echoes
  // Between consecutive groups: the 2*3.0/343 = 17.5 ms echo time of flight at range_max plus
  // margin for the echoes to die down (a full ring every 180 ms, each sensor at 5.6 Hz).
  double group_period_s = 0.03;
  // Each group fires after group_period_s plus a random delay in [0, group_jitter_s] (its own
  // random stream): an echo of an earlier ping that arrives in a later listening window then
  // reads a different range every ring cycle instead of the same one (Borenstein & Koren's
  // varied firing delays against crosstalk, the paper's ref. [6]); 0: a fixed schedule.
  double group_jitter_s = 0.008;
  // [s] The sonar's host clock minus the odometry's: SONAR_RING, SONAR_TRUTH and SONAR_GEOMETRY
  // are stamped this much later than the firing. 0: one clock (README "Clocks").
  double clock_offset_s = 0;
  // [s] How long after its firing a group's SONAR_RING (and SONAR_TRUTH) is sent: a driver has
  // the group's ranges only once its listening window has closed, 2 * range_max / 343 m/s
  // (17.5 ms at 3 m); a negative value means that window. 0: at the firing (the message is
  // stamped with the firing time either way).
  double send_delay_s = -1;
  // The send delay in effect: send_delay_s, or the listening window where it is negative.
  double sendDelay() const { return send_delay_s >= 0 ? send_delay_s : timeOfFlight(range_max); }
  // The simulated transducer's beam, relative to the nominal beam_width the driver publishes in
  // SONAR_RING (which the pipeline assumes): 0.8 = every lobe 20 % narrower.
  double beam_scale = 1.0;
  // What SONAR_RING says the beam is: false, the nominal beam_width (a datasheet's, whatever
  // the transducer really does); true, nominal * beam_scale (a driver calibrated to its
  // transducer: what an exact estimate of the beam width would give the pipeline).
  bool report_scaled_beam = false;
  double noise_std = 0.01;            // [m] + noise_rel * range
  double noise_rel = 0.01;
  int multipath_bounces = 3;          // specular reflections followed (1: a single mirror)
  double foreign_prob = 0.01;         // per reading: an unmodelled foreign ultrasound source
  // --- ideal profile
  // 0.5 deg apart across a 30 deg beam: a 4 cm pipe at range_max still meets a ray.
  int rays_per_beam = 61;
  double multipath_prob = 0.5;        // specular miss -> a too-long reading (else no echo)
  double crosstalk_prob = 0.02;       // per reading (also the physical profile's crosstalk: random)
  // --- physical profile (sim/acoustics.hpp, README "Sensor models")
  double frequency_hz = 49'400;       // Polaroid 6500 ranging module
  double transducer_radius = 0.0192;  // [m] Polaroid 600-series electrostatic transducer
  int pulse_cycles = 16;              // the 6500 module's burst
  bool side_lobes = true;
  double plane_range = 10.7;          // [m] a flat wall is detected up to here (35 ft, 6500 module)
  double tvg_range = 1.0;             // [m] the gain reaches full gain at this echo range
  double air_absorption = -1;         // [dB/m]; < 0: ISO 9613-1 at frequency_hz, 20 °C, 50 % RH
  double ray_step = 0.5 * geom::kPi / 180;  // [rad] between rays across the beam
  CrosstalkModel crosstalk = CrosstalkModel::Geometric;
  // The ideal beam of the hypothetical scan (README "Method, as implemented", step 2), for
  // SONAR_TRUTH.nearest_laser_visible: keep it equal to the complement's sector.
  double ideal_beam_width = 30 * geom::kPi / 180;  // [rad]
  double ideal_range = 2.20;                       // [m]
};
// Keys of `c` replace those of `base`; `ring` or `sensors` replaces the whole sensor set.
SonarConfig sonarConfig(const Config& c, SonarConfig base = {});
// As checkOdometryKeys, for a sonar section (range_min < range_max, group_period_s against the
// echo time of flight, ... are checked with its base).
void checkSonarKeys(const Config& c);

class PhysicalSonar;  // sim/sonar_physical.hpp

// Fires the groups one after another, every group_period_s from the first SIM_STATE on, with
// the truth interpolated to each firing time.
class SonarDriverCore {
 public:
  // seed: the scenario's; the sonar's own stream is deriveSeed(seed, "sonar").
  SonarDriverCore(const Scenario& s, const SonarConfig& c, uint64_t seed);
  ~SonarDriverCore();
  SonarDriverCore(SonarDriverCore&&) noexcept;
  SonarDriverCore& operator=(SonarDriverCore&&) noexcept;
  struct Output {
    sonar_ring_t ring;
    sonar_truth_t truth;
  };
  // Every group whose SONAR_RING is due at or before st.utime: fired at least sendDelay()
  // earlier (each computed at its firing time). A state not after the previous one, with a
  // non-finite value or an unknown mover id is refused with std::invalid_argument (nothing
  // changes).
  std::vector<Output> onSimState(const sim_state_t& st);
  sonar_geometry_t geometry(int64_t utime) const;

 private:
  Output fire(int64_t utime, const sim_state_t& truth);

  std::unique_ptr<const Scenario> scenario_;  // heap: world_ points into it, cores stay movable
  SonarConfig config_;
  WorldGeometry world_;
  std::mt19937_64 rng_;
  std::vector<std::vector<int>> groups_;  // sensor ids of each firing group, ascending
  int64_t period_us_;
  std::optional<sim_state_t> last_;       // previous SIM_STATE, to interpolate the truth
  int64_t next_fire_utime_ = 0;
  std::mt19937_64 schedule_rng_;          // group_jitter_s
  std::vector<std::pair<int64_t, Output>> pending_;  // fired, not yet sent: (due utime, output)
  int32_t seq_ = 0;
  std::unique_ptr<PhysicalSonar> physical_;     // the physical profile's state (pings, fluctuations)
  std::vector<geom::Vec2> mover_velocity_;      // true, from the last two SIM_STATEs, by mover id
};

}  // namespace lasonic::sim
