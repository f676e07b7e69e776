#pragma once
// Ray casting in the simulated world: static primitives plus the movers at one instant.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sim/scenario.hpp"

namespace lasonic::sim {

struct Hit {
  double range = 0;          // [m] along the ray
  geom::Vec2 point;          // global (true) frame
  geom::Vec2 normal;         // unit surface normal, facing the ray origin
  const Primitive* primitive = nullptr;
  int obstacle = -1;         // as Primitive::obstacle
};

// Mover positions at one instant (true frame), index = mover id.
struct MoverPose {
  int id = 0;
  geom::Vec2 position;
  double radius = 0;
};

// Clearance of a point from one static primitive [m]: its distance from a segment, or from a
// circle's rim (negative inside the circle, which is solid). A body of radius r at q overlaps
// the primitive when this is below r.
double clearance(const Primitive& p, const geom::Vec2& q);
// The least clearance of any point of the segment s: a body's centre travelling along it.
double clearance(const Primitive& p, const geom::Segment& s);

// Where the robot's disc (robot.radius), driven along its path for duration_s, first overlaps a
// static obstacle: one per obstacle, in the order they are met. Boxes and circles are solid (a
// robot standing inside one overlaps it); a polyline is its walls, as a room's are. The path is
// sampled every step_m (its stretch between samples is checked whole, so nothing thin is
// missed); `at` and `t` are the first sample found overlapping.
struct RobotOverlap {
  int obstacle = -1;  // index into Scenario::obstacles
  geom::Vec2 at;      // the robot's centre [m]
  double t = 0;       // sim time [s]
};
std::vector<RobotOverlap> robotOverlaps(const Scenario& s, double step_m = 0.02);
// The warning for one: "robot.path: the robot (radius 0.35) overlaps obstacles[3] at (2.10, 1.00)
// (t ≈ 4.2 s)" (README "Scenario format").
std::string describeRobotOverlap(const Scenario& s, const RobotOverlap& o);

// The same for each mover's disc along its own path (its start delay counted; a mover that waits
// for the robot meets the place later, never elsewhere): a person drawn walking through a pane or
// a wall, whom the simulator would carry through it as it does the robot.
struct MoverOverlap {
  int mover = -1;  // index into Scenario::movers
  RobotOverlap where;
};
std::vector<MoverOverlap> moverOverlaps(const Scenario& s, double step_m = 0.02);
// "movers[1].path: the mover (radius 0.25) overlaps obstacles[3] at (4.00, 3.15) (t ≈ 5.3 s, later
// if it waits for the robot)" (without the "later" for a mover that does not avoid the robot).
std::string describeMoverOverlap(const Scenario& s, const MoverOverlap& o);

// The range along `ray` to primitive p (geom::intersect), except that a ray from a point on a
// segment — within kOnSurfaceM, rounding: a transducer flush with a box's face — meets it at 0
// whichever way the rounding fell, as a ray from inside a circle does. Else half the rays from
// such a point would start just beyond the face, pass into the solid and hear its far side.
inline constexpr double kOnSurfaceM = 1e-9;
std::optional<double> rangeAlong(const geom::Ray& ray, const Primitive& p);

class WorldGeometry {
 public:
  explicit WorldGeometry(const Scenario& scenario);

  // Replaces the movers' primitives with their positions at one instant.
  void setMovers(const std::vector<MoverPose>& movers);

  // Nearest hit within max_range. Primitives for which `passes` returns true are ignored
  // (e.g. the laser goes through transparent materials). passes == nullptr: nothing passes.
  std::optional<Hit> castRay(const geom::Ray& ray, double max_range,
                             const std::function<bool(const Material&)>& passes = nullptr) const;

  // The same, with nothing passing, among the static primitives with the given indices (into
  // primitives()) and every mover: for callers that cull what a ray can meet.
  std::optional<Hit> castRayAmong(const geom::Ray& ray, double max_range, const std::vector<uint32_t>& statics) const;

  // All primitives (statics then movers), for sector queries by the evaluation.
  const std::vector<Primitive>& primitives() const { return prims_; }
  const Scenario& scenario() const { return *scenario_; }
  size_t staticCount() const { return n_static_; }

 private:
  Hit makeHit(const geom::Ray& ray, double t, const Primitive& p) const;
  const Scenario* scenario_;
  size_t n_static_ = 0;
  std::vector<Primitive> prims_;
};

}  // namespace lasonic::sim
