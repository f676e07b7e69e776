#pragma once
// Ray casting in the simulated world: static primitives plus the movers at one instant.
#include <cstdint>
#include <functional>
#include <optional>
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
