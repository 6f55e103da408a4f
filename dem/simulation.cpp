// Simulation: the scene built (bodies, walls, boxes), prepared for stepping, and restored springs.
#include "dem/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "dem/chunked.hpp"
#include "dem/time_step.hpp"

namespace mfdem::dem {
namespace {

// 2/5: moment of inertia of a solid sphere is (2/5) m R^2.
constexpr double kSphereInertiaFactor = 0.4;
constexpr double kPi = 3.14159265358979323846;

}  // namespace

Simulation::Simulation(Domain domain, MaterialTable materials, SimulationSettings settings)
    : domain_(std::move(domain)), materials_(std::move(materials)), settings_(settings) {
  bodies_.first_element.push_back(0);
}

ClumpSpec sphere_body(const SphereSpec& s, double density) {
  const double mass = density * 4.0 / 3.0 * kPi * s.radius * s.radius * s.radius;
  ClumpSpec body;
  body.position = s.position;
  body.velocity = s.velocity;
  body.angular_velocity = s.angular_velocity;
  body.mass = mass;
  body.principal_inertia = Vec3::Constant(kSphereInertiaFactor * mass * s.radius * s.radius);
  body.pebbles = {Pebble{Vec3::Zero(), s.radius}};
  body.material = s.material;
  return body;
}

Index Simulation::add_sphere(const SphereSpec& s) {
  if (s.material < 0 || s.material >= materials_.size())
    throw std::invalid_argument(fmt::format("sphere material index {} is not defined", s.material));
  if (!(s.radius > 0.0))
    throw std::invalid_argument(fmt::format("sphere radius must be > 0 m (got {})", s.radius));
  return add_body(sphere_body(s, materials_[s.material].density));
}

Index Simulation::add_clump(const ClumpSpec& c) {
  if (c.material < 0 || c.material >= materials_.size())
    throw std::invalid_argument(fmt::format("clump material index {} is not defined", c.material));
  if (c.pebbles.empty()) throw std::invalid_argument("a clump needs at least one pebble");
  if (!(c.mass > 0.0) || !(c.principal_inertia.minCoeff() > 0.0))
    throw std::invalid_argument("a clump needs a positive mass and principal inertia");
  for (const auto& p : c.pebbles)
    if (!(p.radius > 0.0))
      throw std::invalid_argument(fmt::format("pebble radius must be > 0 m (got {})", p.radius));
  return add_body(c);
}

Index Simulation::add_body(const ClumpSpec& c) {
  if (prepared_) throw std::logic_error("bodies must be added before prepare()");
  const Index b = bodies_.size();
  bodies_.position.push_back(c.position);
  bodies_.velocity.push_back(c.velocity);
  bodies_.angular_velocity.push_back(c.angular_velocity);
  // A unit quaternion is kept as given, so that a body saved and added again is bitwise the same.
  const Quat q = std::abs(c.orientation.squaredNorm() - 1.0) <= 4.0 * std::numeric_limits<double>::epsilon()
                     ? c.orientation : c.orientation.normalized();
  bodies_.orientation.push_back(q);
  bodies_.mass.push_back(c.mass);
  bodies_.inertia.push_back(c.principal_inertia);
  bodies_.local_damping.push_back(materials_[c.material].local_damping);
  bodies_.force.push_back(Vec3::Zero());
  bodies_.unbalanced_force.push_back(Vec3::Zero());
  bodies_.torque.push_back(Vec3::Zero());
  for (const auto& p : c.pebbles) {
    elements_.position.push_back(c.position + q * p.offset);
    elements_.offset.push_back(p.offset);
    elements_.radius.push_back(p.radius);
    elements_.material.push_back(c.material);
    elements_.body.push_back(b);
  }
  bodies_.first_element.push_back(elements_.size());
  point_body_.push_back(c.pebbles.size() == 1 && c.pebbles[0].offset.isZero());
  wrap_total_.push_back(Vec3::Zero());
  return b;
}

int Simulation::add_wall(const PlaneWall& wall) {
  if (prepared_) throw std::logic_error("add_wall after prepare()");
  if (wall.material < 0 || wall.material >= materials_.size())
    throw std::invalid_argument(fmt::format("wall '{}' material index {} is not defined",
                                            wall.name, wall.material));
  PlaneWall w = wall;
  const double norm = w.normal.norm();
  if (!(norm > 0.0)) throw std::invalid_argument("wall '" + w.name + "' has a zero normal");
  w.normal /= norm;
  walls_.push_back(w);
  return static_cast<int>(walls_.size()) - 1;
}

int Simulation::add_box(const RigidBox& box) {
  if (prepared_) throw std::logic_error("add_box after prepare()");
  if (box.material < 0 || box.material >= materials_.size())
    throw std::invalid_argument(fmt::format("box '{}' material index {} is not defined", box.name, box.material));
  if (!(box.mass > 0.0) || !(box.half_extent.minCoeff() > 0.0))
    throw std::invalid_argument(fmt::format("box '{}' needs a positive mass and size", box.name));
  boxes_.push_back(box);
  return static_cast<int>(boxes_.size()) - 1;
}

TimeStepLimit Simulation::stability_limit() const {
  // A box meets the elements like a wall of its material (it is far heavier than a stone).
  std::vector<PlaneWall> boundaries = walls_;
  for (const auto& box : boxes_) boundaries.push_back(PlaneWall{box.name, box.centre, Vec3::UnitZ(), Vec3::Zero(), box.material});
  return critical_time_step(bodies_, elements_, materials_, boundaries);
}

void Simulation::prepare() {
  limit_ = stability_limit();
  const double given = settings_.time_step;
  if (given > 0.0) {
    if (given > limit_.limit && limit_.contact_possible && !settings_.force_time_step)
      throw TimeStepAboveLimitError(fmt::format(
          "time step {:.4g} s is above the stability limit {:.4g} s set by the {}; use a step "
          "<= {:.4g} s (automatic: {:.2g} x limit = {:.4g} s) or force it",
          given, limit_.limit, limit_.reason, limit_.limit, settings_.time_step_safety,
          settings_.time_step_safety * limit_.limit));
    dt_ = given;
  } else {
    if (!std::isfinite(limit_.limit))
      throw std::invalid_argument("automatic time step: no contact can occur; give time_step");
    dt_ = settings_.time_step_safety * limit_.limit;
  }
  double min_radius = std::numeric_limits<double>::infinity();
  largest_radius_ = 0.0;
  for (double r : elements_.radius) {
    min_radius = std::min(min_radius, r);
    largest_radius_ = std::max(largest_radius_, r);
  }
  base_skin_ = settings_.skin > 0.0 ? settings_.skin : kBaseSkinPerSmallestRadius * (std::isfinite(min_radius) ? min_radius : 0.01);
  skin_ = base_skin_;
  check_boxes_clear_periodic_faces();

  const Index ne = elements_.size();
  const std::size_t nw = walls_.size();
  wall_history_.assign(ne * nw, ContactHistory{});
  wall_active_.assign(ne * nw, 0);
  wall_force_.assign(nw, Vec3::Zero());
  const std::size_t nx = boxes_.size();
  box_history_.assign(ne * nx, ContactHistory{});
  box_active_.assign(ne * nx, 0);
  box_force_.assign(nx, Vec3::Zero());
  box_face_force_.assign(nx, zero_box_faces());
  chunk_wall_force_.assign(chunk_count(bodies_.size()) * nw, Vec3::Zero());
  prepared_ = true;
  clump_bodies_.clear();
  for (Index b = 0; b < bodies_.size(); ++b)
    if (!point_body_[b]) clump_bodies_.push_back(b);
  any_periodic_ = domain_.periodic[0] || domain_.periodic[1] || domain_.periodic[2];
  any_rolling_ = false;
  for (int a = 0; a < materials_.size(); ++a)
    for (int b = 0; b < materials_.size(); ++b) any_rolling_ = any_rolling_ || materials_.pair(a, b).rolling_friction > 0.0;
  all_point_bodies_ = std::all_of(point_body_.begin(), point_body_.end(), [](auto f) { return f != 0; });
  const auto& m = elements_.material;
  one_material_ = !m.empty() && std::all_of(m.begin(), m.end(), [&](int k) { return k == m.front(); }) ? m.front() : -1;
  for (Index b = 0; b < bodies_.size(); ++b) update_element_positions(b);
  std::fill(bodies_.force.begin(), bodies_.force.end(), Vec3::Zero());  // the pair loop's sums start here
  std::fill(bodies_.torque.begin(), bodies_.torque.end(), Vec3::Zero());
  rebuild();
  apply_initial_springs();
  gather_and_kick_ = false;
  evaluate_forces();
  gather_and_kick_ = true;

  const EnergyReport e = energy();
  energy_reference_ = e.total();
  double weight = 0.0;
  for (double m : bodies_.mass) weight += m * settings_.gravity.norm();
  const Vec3 extent = domain_.length();
  const Vec3 g_dir = settings_.gravity.norm() > 0 ? Vec3(settings_.gravity.normalized()) : Vec3::Zero();
  const double height = std::abs(extent[0] * g_dir[0]) + std::abs(extent[1] * g_dir[1]) +
                        std::abs(extent[2] * g_dir[2]);
  energy_scale_ = weight * height + e.kinetic() + e.elastic;
  last_good_ = snapshot();
}

void Simulation::set_initial_springs(std::vector<SpringState> springs) {
  if (prepared_) throw std::logic_error("set_initial_springs after prepare()");
  initial_springs_ = std::move(springs);
}

void Simulation::apply_initial_springs() {
  const Index ne = elements_.size();
  const auto nw = static_cast<Index>(walls_.size()), nx = static_cast<Index>(boxes_.size());
  auto refuse = [](const SpringState& s, const std::string& why) {
    throw std::invalid_argument(fmt::format("initial spring ({} {}, {}): {}",
                                            s.kind == SpringState::Kind::kPair   ? "elements"
                                            : s.kind == SpringState::Kind::kWall ? "element and wall"
                                                                                 : "element and box",
                                            s.first, s.second, why));
  };
  for (const SpringState& s : initial_springs_) {
    if (s.first < 0 || s.first >= ne) refuse(s, fmt::format("element out of range (0-{})", ne - 1));
    switch (s.kind) {
      case SpringState::Kind::kPair: {
        if (s.second <= s.first || s.second >= ne) refuse(s, "second element out of range or not after the first");
        Index found = -1;
        for (Index p = pairs_.row_start[s.first]; p < pairs_.row_start[s.first + 1]; ++p)
          if (pairs_.second[p] == s.second) found = p;
        if (found < 0) refuse(s, "the elements are not neighbours (not the bed the springs were saved from?)");
        set_pair_history(found, s.history);
        pair_active_[found] = 1;
        break;
      }
      case SpringState::Kind::kWall:
        if (s.second < 0 || s.second >= nw) refuse(s, fmt::format("wall out of range (0-{})", nw - 1));
        wall_history_[s.first * nw + s.second] = s.history;
        wall_active_[s.first * nw + s.second] = 1;
        break;
      case SpringState::Kind::kBox:
        if (s.second < 0 || s.second >= nx) refuse(s, fmt::format("box out of range (0-{})", nx - 1));
        box_history_[s.first * nx + s.second] = s.history;
        box_active_[s.first * nx + s.second] = 1;
        break;
    }
  }
  initial_springs_.clear();
}

std::vector<SpringState> Simulation::contact_springs() const {
  std::vector<SpringState> out;
  for (Index p = 0; p < pairs_.size(); ++p)
    if (pair_active_[p]) out.push_back({SpringState::Kind::kPair, pairs_.first[p], pairs_.second[p], pair_history(p)});
  const auto nw = static_cast<Index>(walls_.size()), nx = static_cast<Index>(boxes_.size());
  for (Index e = 0; e < elements_.size(); ++e) {
    for (Index w = 0; w < nw; ++w)
      if (wall_active_[e * nw + w]) out.push_back({SpringState::Kind::kWall, e, w, wall_history_[e * nw + w]});
    for (Index k = 0; k < nx; ++k)
      if (box_active_[e * nx + k]) out.push_back({SpringState::Kind::kBox, e, k, box_history_[e * nx + k]});
  }
  return out;
}

// A box sees each element at its periodic image nearest the box's centre (box_image), so it may
// lie anywhere, across a periodic face too; but the gap it leaves to its own image must be wider
// than any element, or an element in it would touch both and be seen by one.
void Simulation::check_boxes_clear_periodic_faces() const {
  for (const auto& box : boxes_)
    for (int a = 0; a < 3; ++a) {
      if (!domain_.periodic[a]) continue;
      const double gap = domain_.length()[a] - 2.0 * box.half_extent[a];
      if (gap <= 2.0 * largest_radius_)
        throw std::invalid_argument(fmt::format(
            "box '{}' is {:.4g} m long along the periodic axis {} of length {:.4g} m: the gap to its periodic "
            "image, {:.4g} m, must be wider than the largest element diameter {:.4g} m",
            box.name, 2.0 * box.half_extent[a], "xyz"[a], domain_.length()[a], gap, 2.0 * largest_radius_));
    }
}

void Simulation::update_element_positions(Index b) {
  if (point_body_[b]) {
    elements_.position[bodies_.element_begin(b)] = bodies_.position[b];
    return;
  }
  place_elements(b, bodies_.orientation[b].toRotationMatrix());
}

void Simulation::place_elements(Index b, const Mat3& rotation) {
  const Index end = bodies_.element_end(b);
  for (Index e = bodies_.element_begin(b); e < end; ++e)
    elements_.position[e] = bodies_.position[b] + rotation * elements_.offset[e];
}

}  // namespace mfdem::dem
