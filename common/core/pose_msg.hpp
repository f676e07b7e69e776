#pragma once
// Between the wire's pose2d_t and the geometry's Pose2, one place for every library that
// reads or writes poses in messages. Header-only: lasonic_core does not link the message
// types, each user does (lasonic::lcmtypes).
#include <cmath>

#include <lasonic/pose2d_t.hpp>

#include "core/geometry.hpp"

namespace lasonic {

inline geom::Pose2 toPose(const pose2d_t& m) { return {m.x, m.y, m.theta}; }

inline pose2d_t toPoseMsg(const geom::Pose2& p) {
  pose2d_t m;
  m.x = p.x;
  m.y = p.y;
  m.theta = p.theta;
  return m;
}

inline bool finitePose(const pose2d_t& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

}  // namespace lasonic
