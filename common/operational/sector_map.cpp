#include "operational/sector_map.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lasonic {

namespace {
bool known(float d) { return d >= 0; }
}  // namespace

SectorMap::SectorMap(const SectorMapParams& p) : p_(p) {
  if (p.sectors < 3 || !(p.robot_radius >= 0) || !(p.max_range > 0) || p.gp_threshold < 1 ||
      !(p.copy_confirm_tolerance >= 0) || !(p.laser_explains_radius >= 0) || !(p.remembered_stale_s > 0))
    throw std::invalid_argument("SectorMap: inconsistent parameters");
  const auto n = static_cast<size_t>(p.sectors);
  laser_now_.resize(n);
  sonar_own_.resize(n);
  sonar_reach_.resize(n);
  sonar_now_.resize(n);
  held_laser_.resize(n);
  held_sonar_.resize(n);
  remembered_now_.resize(n);
  s_.distance.assign(n, -1);
  s_.remembered.assign(n, -1);
  s_.laser.assign(n, -1);
  s_.sonar.assign(n, -1);
  s_.source.assign(n, SectorSource::None);
}

int SectorMap::sectorOf(double bearing) const { return sectorOfNormalized(geom::normalizeAngle(bearing)); }

int SectorMap::sectorOfNormalized(double bearing) const {
  const int k = static_cast<int>(std::floor((bearing + geom::kPi) * (p_.sectors / (2.0 * geom::kPi))));
  return k >= p_.sectors ? k - p_.sectors : std::max(k, 0);  // bearing pi is -pi: sector 0
}

void SectorMap::setLaserPoints(int64_t utime, std::vector<geom::Vec2> points) {
  laser_points_ = std::move(points);
  laser_utime_ = utime;
  have_laser_ = true;
  explained_cell_size_ = 0;  // rebuilt for the AGM's cell size at the next update
}

void SectorMap::rebuildExplained(double c) {
  // Once per scan (not per map): the global cells whose centres lie within the radius of a point.
  explained_.clear();
  explained_cell_size_ = c;
  const double rho = p_.laser_explains_radius;
  if (!(rho > 0)) return;
  const auto global = [c](double v) { return static_cast<int64_t>(std::clamp(std::floor(v / c), -1e15, 1e15)); };
  const int64_t span = static_cast<int64_t>(std::ceil(rho / c)) + 1;
  for (const auto& p : laser_points_) {
    const int64_t gx = global(p.x()), gy = global(p.y());
    for (int64_t y = gy - span; y <= gy + span; ++y)
      for (int64_t x = gx - span; x <= gx + span; ++x)
        if ((geom::Vec2((static_cast<double>(x) + 0.5) * c, (static_cast<double>(y) + 0.5) * c) - p).norm() <= rho)
          explained_.emplace_back(x, y);
  }
  std::sort(explained_.begin(), explained_.end());
  explained_.erase(std::unique(explained_.begin(), explained_.end()), explained_.end());
}

void SectorMap::setSonarTime(int64_t utime) {
  sonar_utime_ = utime;
  have_sonar_ = true;
}

void SectorMap::setRemembered(int64_t utime, std::vector<geom::Vec2> points) {
  remembered_points_ = std::move(points);
  remembered_utime_ = utime;
  have_remembered_ = true;
}

bool SectorMap::explained(const geom::Vec2& p) const {
  if (explained_.empty() || !(explained_cell_size_ > 0)) return false;
  const auto global = [this](double v) {
    return static_cast<int64_t>(std::clamp(std::floor(v / explained_cell_size_), -1e15, 1e15));
  };
  return std::binary_search(explained_.begin(), explained_.end(), std::make_pair(global(p.x()), global(p.y())));
}

void SectorMap::rememberedValues(const geom::Pose2& pose, std::vector<Value>& out) const {
  std::fill(out.begin(), out.end(), Value{});
  const double reach = p_.robot_radius + p_.max_range;
  for (const auto& p : remembered_points_) {
    const geom::Vec2 d = p - pose.position();
    const double r = d.norm();
    if (!(r <= reach)) continue;
    if (explained(p)) continue;  // the laser reports it, at its own bearing
    const double dist = std::max(0.0, r - p_.robot_radius);
    if (dist > p_.max_range) continue;
    Value& v = out[static_cast<size_t>(sectorOf(std::atan2(d.y(), d.x()) - pose.theta))];
    if (!known(v.d) || dist < v.d) v = {static_cast<float>(dist), SectorSource::Remembered};
  }
}

void SectorMap::laserValues(const geom::Pose2& pose, std::vector<Value>& out) const {
  std::fill(out.begin(), out.end(), Value{});
  // "Moved into the current pose": global -> robot frame (Pose2::inverseTransform, with the
  // rotation computed once per map instead of once per point).
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const double reach = p_.robot_radius + p_.max_range;
  for (const auto& p : laser_points_) {
    const double dx = p.x() - pose.x, dy = p.y() - pose.y;
    const double r2 = dx * dx + dy * dy;
    if (r2 > reach * reach) continue;
    const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
    const double d = std::max(0.0, std::sqrt(r2) - p_.robot_radius);
    Value& v = out[static_cast<size_t>(sectorOfNormalized(std::atan2(ly, lx)))];
    if (!known(v.d) || d < v.d) v = {static_cast<float>(d), SectorSource::Laser};
  }
}

template <typename Grid>
void SectorMap::sonarValues(const geom::Pose2& pose, const Grid& agm, bool use_explained,
                            std::vector<Value>& out, std::vector<Value>& spread) const {
  std::fill(out.begin(), out.end(), Value{});
  std::fill(spread.begin(), spread.end(), Value{});
  const bool extent = p_.copy_rule == CopyRule::CellExtent;
  const int n = p_.sectors;
  const bool check = use_explained && !explained_.empty();
  const int64_t ox = agm.originX(), oy = agm.originY();
  const double c = agm.cellSize();
  const double reach = p_.robot_radius + p_.max_range;
  const geom::Vec2 o = agm.originMetres();
  const geom::Vec2 robot = pose.position();
  const auto cell = [&](double v, double origin) { return static_cast<int>(std::floor((v - origin) / c)); };
  agm.forEachCell(cell(robot.x() - reach, o.x()), cell(robot.y() - reach, o.y()), cell(robot.x() + reach, o.x()),
                  cell(robot.y() + reach, o.y()), [&](int ix, int iy, int, int gp) {
                    if (gp < p_.gp_threshold) return;
                    if (check && std::binary_search(explained_.begin(), explained_.end(),
                                                    std::make_pair(ox + ix, oy + iy)))
                      return;
                    const geom::Vec2 lo = o + geom::Vec2(ix * c, iy * c);
                    const geom::Vec2 centre = lo + geom::Vec2(0.5 * c, 0.5 * c) - robot;
                    const geom::Vec2 nearest(std::clamp(robot.x(), lo.x(), lo.x() + c),
                                             std::clamp(robot.y(), lo.y(), lo.y() + c));
                    const double r =
                        p_.sonar_cell_point == CellPoint::Centre ? centre.norm() : (nearest - robot).norm();
                    const double d = std::max(0.0, r - p_.robot_radius);
                    if (d > p_.max_range) return;
                    const double bearing = std::atan2(centre.y(), centre.x()) - pose.theta;
                    const int k0 = sectorOf(bearing);
                    Value& v = out[static_cast<size_t>(k0)];
                    if (!known(v.d) || d < v.d) v = {static_cast<float>(d), SectorSource::Sonar};
                    if (!extent) return;
                    // CellExtent: the obstacle is somewhere in the cell's square, so also in every
                    // other sector the square reaches (its half-diagonal seen from the robot).
                    const double half = std::asin(std::min(1.0, (c * 0.7071067811865476) / std::max(centre.norm(), c)));
                    const int k_lo = sectorOf(bearing - half), k_hi = sectorOf(bearing + half);
                    for (int k = k_lo;; k = (k + 1) % n) {
                      if (k != k0) {
                        Value& r2 = spread[static_cast<size_t>(k)];
                        if (!known(r2.d) || d < r2.d) r2 = {static_cast<float>(d), SectorSource::SonarCopied};
                      }
                      if (k == k_hi) break;
                    }
                  });
}

void SectorMap::hold(bool stale, std::vector<Value>& now, std::vector<Value>& held) {
  if (stale) {
    for (size_t k = 0; k < now.size(); ++k)
      if (known(held[k].d) && (!known(now[k].d) || held[k].d < now[k].d)) now[k] = held[k];
  }
  held = now;
}

const SectorMapState& SectorMap::update(int64_t utime, const geom::Pose2& pose, const AccumulativeGridMap& agm) {
  return updateWith(utime, pose, agm);
}

const SectorMapState& SectorMap::update(int64_t utime, const geom::Pose2& pose, const OccupancyWindow& grid) {
  if (grid.size < 0 || grid.occupied.size() != static_cast<size_t>(grid.size) * static_cast<size_t>(grid.size) ||
      !(grid.cell_size > 0))
    throw std::invalid_argument("SectorMap: OccupancyWindow of inconsistent size");
  return updateWith(utime, pose, grid);
}

template <typename Grid>
const SectorMapState& SectorMap::updateWith(int64_t utime, const geom::Pose2& pose, const Grid& agm) {
  const size_t n = static_cast<size_t>(p_.sectors);
  s_.utime = utime;
  s_.pose = pose;
  s_.laser_age_s = have_laser_ ? static_cast<double>(utime - laser_utime_) * 1e-6 : -1.0;
  s_.sonar_age_s = have_sonar_ ? static_cast<double>(utime - sonar_utime_) * 1e-6 : -1.0;
  s_.laser_stale = !have_laser_ || s_.laser_age_s > p_.laser_stale_s;
  s_.sonar_stale = !have_sonar_ || s_.sonar_age_s > p_.sonar_stale_s;
  s_.remembered_age_s = have_remembered_ ? static_cast<double>(utime - remembered_utime_) * 1e-6 : -1.0;
  s_.remembered_stale = !have_remembered_ || s_.remembered_age_s > p_.remembered_stale_s;

  laserValues(pose, laser_now_);
  if (explained_cell_size_ != agm.cellSize()) rebuildExplained(agm.cellSize());
  // A stale scan no longer says what is where: it explains nothing away.
  sonarValues(pose, agm, !s_.laser_stale, sonar_own_, sonar_reach_);
  // Copy rule: own sonar values spread into both neighbours that hold no sonar data of their own
  // (with CopyRule::UnlessLaserConfirmed, not from a sector whose laser value confirms it).
  const bool skip_confirmed = p_.copy_rule == CopyRule::UnlessLaserConfirmed;
  for (size_t k = 0; k < n; ++k) {
    sonar_now_[k] = sonar_own_[k];
    if (known(sonar_own_[k].d)) continue;
    if (p_.copy_rule == CopyRule::CellExtent) {
      sonar_now_[k] = sonar_reach_[k];
      continue;
    }
    for (const size_t j : {(k + n - 1) % n, (k + 1) % n}) {
      const float d = sonar_own_[j].d;
      if (skip_confirmed && known(d) && known(laser_now_[j].d) &&
          std::abs(laser_now_[j].d - d) <= p_.copy_confirm_tolerance)
        continue;
      if (known(d) && (!known(sonar_now_[k].d) || d < sonar_now_[k].d))
        sonar_now_[k] = {d, SectorSource::SonarCopied};
    }
  }
  hold(s_.laser_stale, laser_now_, held_laser_);
  hold(s_.sonar_stale, sonar_now_, held_sonar_);
  // Memory is not held: stale (or never received), it is simply not used.
  if (s_.remembered_stale) std::fill(remembered_now_.begin(), remembered_now_.end(), Value{});
  else rememberedValues(pose, remembered_now_);

  for (size_t k = 0; k < n; ++k) {
    const Value& l = laser_now_[k];
    const Value& s = sonar_now_[k];
    const Value& m = remembered_now_[k];
    const Value* best = (known(l.d) && (!known(s.d) || l.d <= s.d)) ? &l : &s;
    if (known(m.d) && (!known(best->d) || m.d < best->d)) best = &m;
    s_.distance[k] = best->d;
    s_.source[k] = best->src;
    s_.laser[k] = l.d;
    s_.sonar[k] = s.d;
    s_.remembered[k] = m.d;
  }
  return s_;
}

}  // namespace lasonic
