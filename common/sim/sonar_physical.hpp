#pragma once
// The physical sonar model (the default profile; README "Sensor models"): a reading is the first
// echo whose strength exceeds the ranging module's threshold, with echo strengths from
// sim/acoustics.hpp. The ideal profile (sim/sonar_model.hpp, fireSensor) is the method's own
// idealised sonar.
//
// Echoes of one ping, at the transducer that sent it (monostatic):
//  - PLANE: a flat surface answers from the foot of the perpendicular (its coherent, mirror-like
//    share), wherever that lies in the transducer's pattern, side lobes included;
//  - CYLINDER: a circle answers from its nearest point, weaker by its curvature;
//  - CORNER: an inside corner of about 90° (two walls, a wall and a cabinet side) returns the
//    sound to the transducer from any direction inside it, as strong as a plane at the corner's
//    range: a DIRECT echo at the corner's range;
//  - EDGE: a segment end or an outside corner diffracts weakly in every direction;
//  - rough patches: across the beam (rays ray_step apart) every surface scatters its incoherent
//    share back (specular lobe + diffuse part), from the point the ray meets;
//  - SPECULAR_LONG: along each ray the coherent share mirrors on, up to multipath_bounces times;
//    a surface met further on sends its backscatter back the same way (a too-long reading).
// Sound passes through transmitting materials (a mesh) with their loss, both ways.
// Echoes of other pings (bistatic), at a sensor that listens later or at the same time:
//  - CROSSTALK: a sensor of the same firing group hears another's ping via a plane mirror, a
//    corner or a cylinder;
//  - LATE_ECHO: an earlier ping (of any sensor) whose echo, from up to plane_range away, arrives
//    in this firing's listening window; it repeats every ring cycle at the same range;
//  - FOREIGN: a scenario emitter's direct sound.
// The reading is the earliest echo above the threshold; echoes nearer than range_min arrive while
// the receiver is blanked and are lost (the next one is read). A weak echo crosses the threshold
// late (the envelope rises over half the pulse cell), noise is added, and the random foreign
// source (foreign_prob; and crosstalk_prob with crosstalk: random) may replace the reading.
#include <cstdint>
#include <deque>
#include <map>
#include <random>
#include <vector>

#include <lasonic/sonar_cause_t.hpp>

#include "sim/acoustics.hpp"
#include "sim/drivers.hpp"
#include "sim/sonar_model.hpp"

namespace lasonic::sim {

// Inside corners and edges of the static world, found where segments meet: at each junction
// the segments' arms split the plane into wedges; a wedge of 90° ± corner_tolerance is a corner
// (retro-reflector) seen from inside it, a wedge wider than 180° an edge seen from inside it (a
// free segment end: 360°).
struct CornerReflector {
  geom::Vec2 vertex;
  double start = 0, opening = 0;   // the wedge: from heading `start`, counter-clockwise by `opening`
  const Primitive* a = nullptr;    // its two walls (a: the arm at `start`)
  const Primitive* b = nullptr;
};
struct EdgeReflector {
  geom::Vec2 point;
  double start = 0, opening = 0;
  const Primitive* a = nullptr;    // the (more reflective) surface that ends here
  const Primitive* b = nullptr;    // the other one, or nullptr at a free end
};
struct Reflectors {
  std::vector<CornerReflector> corners;
  std::vector<EdgeReflector> edges;
};
Reflectors findReflectors(const std::vector<Primitive>& statics, double corner_tolerance);
// Is the direction from the wedge's apex towards p inside the wedge?
bool insideWedge(double start, double opening, const geom::Vec2& apex, const geom::Vec2& p);

// One echo or arrival at a listening sensor.
struct Echo {
  double range = 0;        // [m] arrival time after the firing × 343 m/s / 2
  double margin = 0;       // [dB] above the threshold (>= 0: detected)
  int8_t cause = sonar_cause_t::CAUSE_DIRECT;
  int8_t reflector = sonar_cause_t::REFLECTOR_NONE;
  const Primitive* prim = nullptr;   // the surface that answered (DIRECT), the first mirror (SPECULAR_LONG)
  geom::Vec2 hit{geom::Vec2::Zero()};
};

class PhysicalSonar {
 public:
  PhysicalSonar(const Scenario& s, const SonarConfig& c, uint64_t seed);

  // One sensor's firing, as in a firing group: its own echoes, the arrivals of the other pings in
  // `history` and of the scenario's emitters. `world` holds the movers at utime;
  // mover_velocity[id] their true velocity (the aspect of a person).
  struct Ping {
    int64_t utime = 0;
    int sensor = 0;
    geom::Pose2 pose;   // true global pose of the transducer
  };
  // Fires one group: the readings of `ids` (true global poses `poses`), remembering the pings.
  std::vector<SonarReading> fireGroup(const WorldGeometry& world, int64_t utime, const std::vector<int>& ids,
                                      const std::vector<geom::Pose2>& poses,
                                      const std::vector<geom::Vec2>& mover_velocity, std::mt19937_64& rng);

  // The parts, for tests: every echo of a ping at its own transducer with its margin (not only
  // the detected ones; blanked ones too), and the arrivals of one ping at another listener.
  std::vector<Echo> ownEchoes(const WorldGeometry& world, const geom::Pose2& sensor, int sensor_id) const;
  std::vector<Echo> arrivals(const WorldGeometry& world, const Ping& ping, const geom::Pose2& listener,
                             int64_t utime, int listener_id) const;
  std::vector<Echo> emitterArrivals(const WorldGeometry& world, const geom::Pose2& listener, int64_t utime) const;

  const acoustics::Transducer& transducer() const { return tx_; }
  const acoustics::EchoBudget& budget() const { return budget_; }
  const Reflectors& reflectors() const { return refl_; }

 private:
  struct Fluct {
    double level = 0;
    int64_t utime = -1;
    std::mt19937_64 rng;
  };
  // dB added to every echo from `obstacle` heard by `sensor` (people: a slowly varying level;
  // 0 for materials without fluctuation).
  double fluctuation(int obstacle, int sensor) const;
  void advanceFluctuation(int sensor, int64_t utime);
  // A mover seen from the side is weaker than head-on.
  double aspectDb(const Primitive& p, const geom::Vec2& from) const;
  // Power lost [dB, <= 0] on the straight path a -> b: the transmitting surfaces on the way, or
  // -inf behind an opaque one. `skip_*` (the reflector itself) are ignored. from_transducer: a is
  // a transducer, stopped at once by a surface it is flush with (rangeAlong). The loss is the same
  // either way along the path, so a leg that ends at a listening transducer is cast from it.
  double transmission(const std::vector<const Primitive*>& prims, const geom::Vec2& a, const geom::Vec2& b,
                      const Primitive* skip_a = nullptr, const Primitive* skip_b = nullptr,
                      bool from_transducer = false) const;
  // Static + mover primitives within `reach` of p.
  std::vector<const Primitive*> near(const WorldGeometry& world, const geom::Vec2& p, double reach) const;
  // A reflector's surface (one of the scenario's statics) as `world` holds it: the ray casts of
  // transmission() skip a surface by its address in the world.
  const Primitive* inWorld(const WorldGeometry& world, const Primitive* stat) const;
  // The coherent and incoherent terms of a material [dB].
  double coherentDb(const Material& m) const;
  double incoherentDb(const Material& m, double beta, double range) const;
  void rayEchoes(const std::vector<const Primitive*>& prims, const geom::Pose2& sensor, int sensor_id,
                 std::vector<Echo>& out) const;

  const Scenario* scenario_;
  SonarConfig cfg_;
  acoustics::Transducer tx_;
  acoustics::EchoBudget budget_;
  Reflectors refl_;
  double fan_;                         // half-width of the ray fan [rad]
  std::vector<double> ray_cos_, ray_sin_;  // the rays' directions off the axis, -fan_ .. fan_
  // Upper bounds over the scenario's materials [dB, relative to a mirror at the same range]: of
  // a rough patch's backscatter, and of anything a ray can bring back (incl. fluctuation).
  double max_incoherent_ = 0, ray_bound_ = 0;
  std::vector<geom::Vec2> mover_velocity_;
  std::map<std::pair<int, int>, Fluct> fluct_;  // (obstacle, sensor) for fluctuating materials
  std::deque<Ping> history_;           // recent pings, oldest first
};

}  // namespace lasonic::sim
