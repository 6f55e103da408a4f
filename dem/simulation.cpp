#include "dem/simulation.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ranges>
#include <stdexcept>

#include "dem/chunked.hpp"
#include "dem/rigid_rotation.hpp"
#include "dem/time_step.hpp"

namespace mfdem::dem {
namespace {

// 2/5: moment of inertia of a solid sphere is (2/5) m R^2.
constexpr double kSphereInertiaFactor = 0.4;
constexpr double kPi = 3.14159265358979323846;
// The automatic skin grows up to this multiple of its packed-bed value (adaptive_skin).
constexpr double kMaxSkinFactor = 5.0;

using BoxFaceForces = std::array<Vec3, kBoxFaces>;
BoxFaceForces zero_faces() {
  BoxFaceForces f;
  f.fill(Vec3::Zero());  // Eigen vectors start uninitialised
  return f;
}

// A body's state is finite: one test of the sum, since a NaN or an infinity in any component
// makes the sum non-finite (a finite state would need components near 1e308 to overflow it).
bool finite_state(const Vec3& x, const Vec3& v, const Vec3& w) { return std::isfinite((x + v + w).sum()); }

// Energy the tangential and rolling springs of a contact that has just opened give up to
// friction, J. The springs are discarded with the contact: in continuous time the Coulomb caps
// (mu Fn, mu_r Rbar Fn -> 0 with the overlap) slip them to zero just before it opens. Part of
// their energy has already gone into the motion: this step's first half kick applied the last
// spring force and moment over dt/2, at relative tangential velocity vt and rolling velocity
// w_roll (b relative to a). Without this account a contact that opens with a loaded spring
// (large mu or mu_r) loses energy that the balance never sees.
double released_spring_energy(const PairParameters& p, const ContactHistory& h, double rbar,
                              const Vec3& vt, const Vec3& w_roll, double dt) {
  double e = h.shear_force.squaredNorm() / (2.0 * p.shear_stiffness) -
             0.5 * dt * h.shear_force.dot(vt);
  if (p.rolling_friction > 0.0)
    e += h.rolling_moment.squaredNorm() / (2.0 * p.shear_stiffness * rbar * rbar) -
         0.5 * dt * h.rolling_moment.dot(w_roll);
  return std::max(0.0, e);
}

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

void Simulation::prepare() {
  // A box meets the elements like a wall of its material (it is far heavier than a stone).
  std::vector<PlaneWall> boundaries = walls_;
  for (const auto& box : boxes_) boundaries.push_back(PlaneWall{box.name, box.centre, Vec3::UnitZ(), Vec3::Zero(), box.material});
  limit_ = critical_time_step(bodies_, elements_, materials_, boundaries);
  const double given = settings_.time_step;
  if (given > 0.0) {
    if (given > limit_.limit && !settings_.force_time_step)
      throw std::invalid_argument(fmt::format(
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
  base_skin_ = settings_.skin > 0.0 ? settings_.skin : 0.2 * (std::isfinite(min_radius) ? min_radius : 0.01);
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
  box_face_force_.assign(nx, zero_faces());
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

// Box contacts take element positions as integrated, not their periodic images. That is exact
// while a box keeps off the periodic faces: an element can be a periodic image away only in
// the skin/2 it moves past a face before the next rebuild wraps it, so a box that stays more
// than the largest radius + the largest skin/2 from a face never meets such an element.
void Simulation::check_boxes_clear_periodic_faces() const {
  const double largest_skin = settings_.skin > 0.0 ? settings_.skin : kMaxSkinFactor * base_skin_;
  const double margin = largest_radius_ + 0.5 * largest_skin;
  for (const auto& box : boxes_)
    for (int a = 0; a < 3; ++a) {
      if (!domain_.periodic[a]) continue;
      const double low = box.centre[a] - box.half_extent[a] - domain_.min[a];
      const double high = domain_.max[a] - (box.centre[a] + box.half_extent[a]);
      if (std::min(low, high) < margin)
        throw std::invalid_argument(fmt::format(
            "box '{}' comes within {:.4g} m of the periodic faces along {} (its extent [{:.4g}, {:.4g}] m "
            "in the domain [{:.4g}, {:.4g}] m); boxes must keep at least the largest element radius + "
            "half the skin = {:.4g} m from them (box contacts do not see periodic images)",
            box.name, std::min(low, high), "xyz"[a], box.centre[a] - box.half_extent[a],
            box.centre[a] + box.half_extent[a], domain_.min[a], domain_.max[a], margin));
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

// Half kick: v += h F/m; the angular momentum takes h T. A point body (sphere) has an isotropic
// inertia, so w += h T/I directly; a clump goes through its body-frame angular momentum.
void Simulation::kick(Index b, const Vec3& force, const Vec3& torque, double h) {
  bodies_.velocity[b] += (h / bodies_.mass[b]) * force;
  if (point_body_[b]) {
    bodies_.angular_velocity[b] += h * torque.cwiseQuotient(bodies_.inertia[b]);
    return;
  }
  // l_body += h R^T T, so w = R (l_body / I) gains R ((h R^T T) / I): no round trip of w
  // through the body frame, and one rotation matrix instead of three quaternion rotations.
  const Mat3 r = bodies_.orientation[b].toRotationMatrix();
  bodies_.angular_velocity[b] += r * (h * (r.transpose() * torque)).cwiseQuotient(bodies_.inertia[b]);
}

// Free axes of a box move under the elements' force, its load and gravity; driven axes keep
// their speed.
void Simulation::kick_boxes(double h) {
  for (std::size_t k = 0; k < boxes_.size(); ++k) {
    RigidBox& box = boxes_[k];
    const Vec3 acceleration = (box_force_[k] + box.applied_force) / box.mass + settings_.gravity;
    for (int a = 0; a < 3; ++a)
      if (!box.driven[a]) box.velocity[a] += h * acceleration[a];
  }
}

Simulation::Snapshot Simulation::snapshot() const {
  return Snapshot{time_, step_count_, bodies_.position, bodies_.velocity,
                  bodies_.angular_velocity, bodies_.orientation};
}

void Simulation::step() {
  if (!prepared_) throw std::logic_error("Simulation::step before prepare()");
  drift_and_kick();
  kick_boxes(0.5 * dt_);
  for (auto& box : boxes_) {
    for (int a = 0; a < 3; ++a)
      if (!box.driven[a]) work_by_walls_ += box.applied_force[a] * box.velocity[a] * dt_;
    box.centre += dt_ * box.velocity;
    box.half_extent += dt_ * box.growth_rate;
  }
  maybe_rebuild();
  evaluate_forces();
  kick_boxes(0.5 * dt_);
  time_ += dt_;
  ++step_count_;
  for (auto& w : walls_) w.point += dt_ * w.velocity;
  if (step_count_ % kBalanceInterval == 0) balance_blocks();
  if (step_count_ % settings_.guards.check_interval == 0) check_stability();
}

void Simulation::drift_and_kick() {
  const Index nb = bodies_.size();
  const double half = 0.5 * dt_;
  double max_move2 = 0.0;
  Index first_bad = nb;
  const int team = team_size();
  // Each thread drifts the bodies it sums the pair forces of (thread_bodies), in one region for
  // spheres and clumps.
#pragma omp parallel num_threads(team) if (team > 1) reduction(max : max_move2) reduction(min : first_bad)
  {
    const auto [b0, b1] = thread_bodies();
    for (Index b = b0; b < b1; ++b) {
      if (!finite_state(bodies_.position[b], bodies_.velocity[b], bodies_.angular_velocity[b]))
        first_bad = std::min(first_bad, b);
      if (!point_body_[b]) continue;  // clumps: below
      kick(b, bodies_.force[b], bodies_.torque[b], half);
      if (all_point_bodies_) {  // the pair loop sums into them (evaluate_forces_of)
        bodies_.force[b] = Vec3::Zero();
        bodies_.torque[b] = Vec3::Zero();
      }
      bodies_.position[b] += dt_ * bodies_.velocity[b];
      const Index e = bodies_.element_begin(b);
      elements_.position[e] = bodies_.position[b];
      max_move2 = std::max(max_move2, (elements_.position[e] - build_position_[e]).squaredNorm());
    }
    // The clump batches that start in this block: the batches themselves do not depend on the
    // split (free_rotations and free_rotation need not agree to the bit).
    const auto first_batch = [&](Index b) {
      const auto i = std::lower_bound(clump_bodies_.begin(), clump_bodies_.end(), b) - clump_bodies_.begin();
      return (static_cast<Index>(i) + kRotationBatch - 1) / kRotationBatch;
    };
    for (Index k = first_batch(b0); k < first_batch(b1); ++k)
      max_move2 = std::max(max_move2, drift_clump_batch(k, half));
  }
  max_move2_ = max_move2;
  // A state made non-finite between steps (by a caller): name that body now, before the contact
  // forces carry the NaN to its neighbours, which gather_chunk would otherwise name.
  if (first_bad < nb)
    fail(fmt::format("body {} has a non-finite position or velocity", first_bad), first_bad);
}

// Clumps k * kRotationBatch onwards, side by side (see free_rotations): half kick straight into
// the body-frame angular momentum, drift, free rotation, and the pebbles placed with the new
// orientation's rotation matrix. Returns the largest squared move of a pebble since the build.
double Simulation::drift_clump_batch(Index k, double half) {
  const Index nc = static_cast<Index>(clump_bodies_.size());
  const Index* batch = &clump_bodies_[k * kRotationBatch];
  const int n = static_cast<int>(std::min<Index>(kRotationBatch, nc - k * kRotationBatch));
  Quat* q[kRotationBatch];
  const Vec3* inertia[kRotationBatch];
  Vec3 l_body[kRotationBatch];
  for (int m = 0; m < n; ++m) {
    const Index b = batch[m];
    bodies_.velocity[b] += (half / bodies_.mass[b]) * bodies_.force[b];
    bodies_.position[b] += dt_ * bodies_.velocity[b];
    q[m] = &bodies_.orientation[b];
    inertia[m] = &bodies_.inertia[b];
    const Mat3 r0 = q[m]->toRotationMatrix();
    l_body[m] = inertia[m]->cwiseProduct(r0.transpose() * bodies_.angular_velocity[b]) +
                half * (r0.transpose() * bodies_.torque[b]);
  }
  if (n == kRotationBatch) {
    free_rotations<kRotationBatch>(q, l_body, inertia, dt_);
  } else {
    for (int m = 0; m < n; ++m) free_rotation(*q[m], l_body[m], *inertia[m], dt_);
  }
  double max_move2 = 0.0;
  for (int m = 0; m < n; ++m) {
    const Index b = batch[m];
    const Mat3 r1 = q[m]->toRotationMatrix();
    bodies_.angular_velocity[b] = r1 * l_body[m].cwiseQuotient(*inertia[m]);
    place_elements(b, r1);
    const Index end = bodies_.element_end(b);
    for (Index e = bodies_.element_begin(b); e < end; ++e)
      max_move2 = std::max(max_move2, (elements_.position[e] - build_position_[e]).squaredNorm());
  }
  return max_move2;
}

void Simulation::maybe_rebuild() {
  if (4.0 * max_move2_ > skin_ * skin_) rebuild();
}

void Simulation::rebuild() {
  // Contacts that opened in this step's drift are released now, while their images are still
  // those of the old list: the new list may no longer hold them (a skin smaller than a step's
  // move), and a released spring must be counted, not lost.
  release_opened_contacts();
  // Wrap bodies that left the periodic box, then rebuild and carry the springs over.
  for (Index b = 0; b < bodies_.size(); ++b) {
    const Vec3 shift = domain_.wrap_shift(bodies_.position[b]);
    if (shift.isZero()) continue;
    bodies_.position[b] += shift;
    wrap_total_[b] += shift;
    update_element_positions(b);
  }
  if (settings_.skin <= 0.0) skin_ = adaptive_skin();
  PairList fresh = build_pair_list(elements_, domain_, skin_);
  const Index n = fresh.size();
  std::vector<PairSpring> springs(n);
  std::vector<Vec3> rolling(n, Vec3::Zero());
  // A carried contact stays active: if it opens at the next step, its spring must still be
  // released (and its energy counted) and cleared, not kept for a later touch.
  std::vector<std::uint8_t> active(n, 0);
  const bool had_list = !pairs_.row_start.empty();
  // Images are relative to the positions of this build; a wrapped body shifts its images.
#pragma omp parallel for schedule(static) if (n > kChunkSize)
  for (Index p = 0; p < n; ++p) {
    if (!had_list) continue;
    const Index i = fresh.first[p], j = fresh.second[p];
    for (Index q = pairs_.row_start[i]; q < pairs_.row_start[i + 1]; ++q) {
      if (pairs_.second[q] != j || !pair_active_[q]) continue;
      springs[p] = pair_spring_[q];
      rolling[p] = pair_rolling_[q];
      active[p] = 1;
      break;
    }
  }
  pairs_ = std::move(fresh);
  pair_blocks_.threads = 0;  // to be planned for the new list
  pair_spring_ = std::move(springs);
  pair_rolling_ = std::move(rolling);
  pair_force_.assign(n, Vec3::Zero());
  pair_torque_first_.assign(n, Vec3::Zero());
  pair_torque_second_.assign(n, Vec3::Zero());
  pair_active_ = std::move(active);
  // The dashpot of each pair: fixed by the two bodies' masses, so computed once per build
  // rather than (a square root and a division) per contact and step.
  pair_dashpot_.resize(n);
  pair_reach2_.resize(n);
#pragma omp parallel for schedule(static) if (n > kChunkSize)
  for (Index p = 0; p < n; ++p) {
    const Index i = pairs_.first[p], j = pairs_.second[p];
    const double reach = elements_.radius[i] + elements_.radius[j];
    pair_reach2_[p] = reach * reach;
    const double mi = bodies_.mass[elements_.body[i]], mj = bodies_.mass[elements_.body[j]];
    const PairParameters& pp = materials_.pair(elements_.material[i], elements_.material[j]);
    pair_dashpot_[p] = damping_coefficient(pp.damping_ratio, mi * mj / (mi + mj), pp.normal_stiffness);
  }
  build_position_ = elements_.position;
  ++rebuilds_;
  scan_walls_ = true;
}

void Simulation::release_opened_contacts() {
  const Vec3 length = domain_.length();
  double released = 0.0;  // summed in pair order: the same on any thread count
  for (Index p = 0; p < pairs_.size(); ++p) {
    if (!pair_active_[p]) continue;
    const Vec3 d = separation(p, length);
    if (!overlapping(p, d.squaredNorm())) released += release_pair(p, d);
  }
  dissipated_friction_ += released;
}

// The automatic skin: the base skin (0.2 x the smallest radius) while the bodies creep, as in a
// packed bed; up to five times more while they fly (a deposition falling at metres per second
// rebuilt every ~15 steps at the base skin, and the builds took over half the time), so that the
// fastest element needs about kStepsPerBuild steps to cross half the skin. Kept below what a
// periodic axis allows (three cells of largest diameter + skin). The skin only decides how often
// the list is rebuilt, never which contacts act (tests/physics/contact_history_rebuild_test.cpp).
double Simulation::adaptive_skin() const {
  constexpr double kStepsPerBuild = 40.0;
  const Index ne = elements_.size();
  double fastest = 0.0;  // m/s: bound on any element's speed, |v| + |w| |lever|
#pragma omp parallel for schedule(static) reduction(max : fastest) if (ne > kChunkSize)
  for (Index e = 0; e < ne; ++e) {
    const Index b = elements_.body[e];
    const double lever = (elements_.position[e] - bodies_.position[b]).norm();
    fastest = std::max(fastest, bodies_.velocity[b].norm() + bodies_.angular_velocity[b].norm() * lever);
  }
  double ceiling = kMaxSkinFactor * base_skin_;
  for (int a = 0; a < 3; ++a)
    if (domain_.periodic[a]) ceiling = std::min(ceiling, domain_.length()[a] / 3.0 - 2.0 * largest_radius_);
  const double wanted = 2.0 * fastest * dt_ * kStepsPerBuild;
  return std::max(base_skin_, std::min(wanted, ceiling));
}

// Marks the elements that may touch a plane wall before the next scan. Until the next
// neighbour-list build an element stays within skin/2 of its build position, so within skin of
// where it is now; a scan is redone when a wall has moved by skin/4 (or turned). An element
// further than 1.5 skin from every wall now therefore stays at least skin/4 clear of them: its
// wall loop would do nothing, and gather_chunk skips it.
void Simulation::scan_walls() {
  const Index ne = elements_.size();
  const std::size_t nw = walls_.size();
  near_wall_.resize(ne);
  const double reach = 1.5 * skin_;
#pragma omp parallel for schedule(static) if (ne > kChunkSize)
  for (Index e = 0; e < ne; ++e) {
    bool near = false;
    for (std::size_t w = 0; w < nw; ++w) {
      const double gap = (elements_.position[e] - walls_[w].point).dot(walls_[w].normal);
      near = near || gap - elements_.radius[e] < reach || wall_active_[e * nw + w];
    }
    near_wall_[e] = near;
  }
  wall_scan_point_.resize(nw);
  wall_scan_normal_.resize(nw);
  for (std::size_t w = 0; w < nw; ++w) {
    wall_scan_point_[w] = walls_[w].point;
    wall_scan_normal_[w] = walls_[w].normal;
  }
  scan_walls_ = false;
}

// A contact that has just opened (separation d): books the energy left in its tangential and
// rolling springs as dissipated, clears them and marks the pair inactive.
double Simulation::release_pair(Index p, const Vec3& d) {
  const Index i = pairs_.first[p], j = pairs_.second[p];
  const Index bi = elements_.body[i], bj = elements_.body[j];
  const double ri = elements_.radius[i], rj = elements_.radius[j];
  const Vec3 n = d.normalized();
  const Vec3& wi = bodies_.angular_velocity[bi];
  const Vec3& wj = bodies_.angular_velocity[bj];
  const Vec3 v = bodies_.velocity[bj] + wj.cross(elements_.position[j] - bodies_.position[bj] - rj * n) -
                 bodies_.velocity[bi] - wi.cross(elements_.position[i] - bodies_.position[bi] + ri * n);
  const Vec3 spin = wj - wi;
  const double energy = released_spring_energy(materials_.pair(elements_.material[i], elements_.material[j]),
                                               pair_history(p), ri * rj / (ri + rj), v - v.dot(n) * n,
                                               spin - spin.dot(n) * n, dt_);
  set_pair_history(p, ContactHistory{});
  pair_active_[p] = 0;
  return energy;
}

template <bool kPointBodies>
void Simulation::prefill_batch(ContactBatch& batch) const {
  const PairParameters* const pp = one_material_ >= 0 ? &materials_.pair(one_material_, one_material_) : nullptr;
  for (int lane = 0; lane < kContactBatch; ++lane) {
    if (kPointBodies) {
      batch.lax[lane] = batch.lay[lane] = batch.laz[lane] = 0.0;
      batch.lbx[lane] = batch.lby[lane] = batch.lbz[lane] = 0.0;
    }
    if (pp) {
      batch.kn[lane] = pp->normal_stiffness, batch.ks[lane] = pp->shear_stiffness;
      batch.mu[lane] = pp->friction, batch.mu_r[lane] = pp->rolling_friction;
    }
    if (!any_rolling_) batch.mx[lane] = batch.my[lane] = batch.mz[lane] = 0.0;
  }
}

template <bool kPointBodies>
void Simulation::load_lane(ContactBatch& batch, int lane, Index p, const Vec3& d, double d2) const {
  const Index i = pairs_.first[p], j = pairs_.second[p];
  // With only spheres, element k is body k and sits at its centre: no indirection, no lever.
  const Index bi = kPointBodies ? i : elements_.body[i];
  const Index bj = kPointBodies ? j : elements_.body[j];
  batch.dx[lane] = d.x(), batch.dy[lane] = d.y(), batch.dz[lane] = d.z();
  batch.d2[lane] = d2;
  batch.ra[lane] = elements_.radius[i], batch.rb[lane] = elements_.radius[j];
  const Vec3& va = bodies_.velocity[bi];
  const Vec3& vb = bodies_.velocity[bj];
  const Vec3& wa = bodies_.angular_velocity[bi];
  const Vec3& wb = bodies_.angular_velocity[bj];
  batch.vax[lane] = va.x(), batch.vay[lane] = va.y(), batch.vaz[lane] = va.z();
  batch.vbx[lane] = vb.x(), batch.vby[lane] = vb.y(), batch.vbz[lane] = vb.z();
  batch.wax[lane] = wa.x(), batch.way[lane] = wa.y(), batch.waz[lane] = wa.z();
  batch.wbx[lane] = wb.x(), batch.wby[lane] = wb.y(), batch.wbz[lane] = wb.z();
  if constexpr (!kPointBodies) {  // spheres: zero levers, set once by prefill_batch
    const Vec3 la = elements_.position[i] - bodies_.position[bi];
    const Vec3 lb = elements_.position[j] - bodies_.position[bj];
    batch.lax[lane] = la.x(), batch.lay[lane] = la.y(), batch.laz[lane] = la.z();
    batch.lbx[lane] = lb.x(), batch.lby[lane] = lb.y(), batch.lbz[lane] = lb.z();
  }
  if (one_material_ < 0) {  // else set once by prefill_batch
    const PairParameters& pp = materials_.pair(elements_.material[i], elements_.material[j]);
    batch.kn[lane] = pp.normal_stiffness, batch.ks[lane] = pp.shear_stiffness;
    batch.mu[lane] = pp.friction, batch.mu_r[lane] = pp.rolling_friction;
  }
  batch.cn[lane] = pair_dashpot_[p];
  const PairSpring& h = pair_spring_[p];
  batch.sx[lane] = h.shear_force.x(), batch.sy[lane] = h.shear_force.y(), batch.sz[lane] = h.shear_force.z();
  if (any_rolling_) {  // else zero, set once by prefill_batch (and the pair's stays zero)
    const Vec3& m = pair_rolling_[p];
    batch.mx[lane] = m.x(), batch.my[lane] = m.y(), batch.mz[lane] = m.z();
  }
  batch.damping_force[lane] = h.damping_force;
}

void Simulation::store_springs(const ContactBatch& batch, int lane, Index p) {
  PairSpring& h = pair_spring_[p];
  h.shear_force = Vec3(batch.sx[lane], batch.sy[lane], batch.sz[lane]);
  h.damping_force = batch.damping_force[lane];
  if (any_rolling_) pair_rolling_[p] = Vec3(batch.mx[lane], batch.my[lane], batch.mz[lane]);
}

// Pair forces, summed into the elements in increasing pair order whatever the thread count:
// element e takes the pairs where it is second (all earlier in the list than its own row), then
// its own row. Each thread owns a block of bodies, their elements and their rows. A pair whose
// second element lies in a later block is computed first and stored (phase A); then each thread
// adds the stored pairs of earlier blocks to its elements and walks its rows in order (phase B).
// One thread is the one-block case: no stored pairs at all.
void Simulation::evaluate_forces() {
  if (all_point_bodies_)
    evaluate_forces_of<true>();
  else
    evaluate_forces_of<false>();
}

// The first body of thread t's block: the blocks split the neighbour list, the pair loop's work,
// at the shares balance_blocks measured (equal shares at first), rather than the bodies (a bed's
// surface or a sparse region has fewer neighbours per body), and start at a chunk so that
// gather_chunk's chunk sums can follow the same split. The result does not depend on where
// the blocks end.
Index Simulation::pair_block_start(int t) const {
  const Index nb = bodies_.size();
  if (t + 1 >= static_cast<int>(pair_blocks_.share.size())) return nb;
  const auto target = static_cast<Index>(static_cast<double>(pairs_.size()) * pair_blocks_.share[t]);
  // The first body whose rows start at or after the target, to the nearest chunk.
  const Index b = *std::ranges::partition_point(std::views::iota(Index{0}, nb), [&](Index b) {
    return pairs_.row_start[bodies_.element_begin(b)] < target;
  });
  return std::min(nb, chunk_begin((b + kChunkSize / 2) / kChunkSize));
}

int Simulation::team_size() const {
  return bodies_.size() > kChunkSize ? omp_get_max_threads() : 1;
}

// Called by every thread of a team (in a parallel region of team_size() threads, or fewer when
// nested): the blocks planned for this team size. Every thread reads the plan's count before any
// can pass the barrier to the re-plan, so all take the same branch.
const Simulation::PairBlocks& Simulation::team_plan() {
  const int nt = omp_get_num_threads();
  if (pair_blocks_.threads != nt) {
#pragma omp barrier
#pragma omp single
    plan_pair_blocks(nt);
  }
  return pair_blocks_;
}

std::pair<Index, Index> Simulation::thread_bodies() {
  const PairBlocks& plan = team_plan();
  const int t = omp_get_thread_num();
  return {plan.body_start[t], plan.body_start[t + 1]};
}

std::pair<Index, Index> Simulation::thread_chunks() {
  const auto [first, end] = thread_bodies();
  return {first / kChunkSize, chunk_count(end)};  // blocks start at chunks
}

// Moves the block boundaries towards equal measured pair-loop time per thread (as LAMMPS's
// fix balance does by time): a block's share of the neighbour list is scaled by how much faster
// than the average its thread was. Only the split moves, never a result.
void Simulation::balance_blocks() {
  PairBlocks& plan = pair_blocks_;
  const int nt = plan.threads;
  if (nt < 2) return;
  double total = 0.0;
  for (int t = 0; t < nt; ++t) total += plan.busy[t].seconds;
  if (!(total > 0.0)) return;
  std::vector<double> share(nt + 1, 0.0);
  for (int t = 0; t < nt; ++t) {
    const double width = plan.share[t + 1] - plan.share[t];
    const double rate = plan.busy[t].seconds / total * nt;  // 1: the average thread
    // Half way to the share that would have taken the average time, as the costs are noisy.
    share[t + 1] = share[t] + width * (0.5 + 0.5 / std::max(rate, 0.25));
  }
  for (int t = 1; t < nt; ++t) share[t] /= share[nt];
  share[nt] = 1.0;
  for (auto& b : plan.busy) b.seconds = 0.0;
  const std::vector<double> old = plan.share;
  plan.share = share;
  bool moved = false;
  for (int t = 1; t < nt; ++t) moved = moved || pair_block_start(t) != plan.body_start[t];
  if (moved)
    plan.threads = 0;  // re-planned at the next step's drift
  else
    plan.share = old;  // the same blocks: the shares stay those of the blocks measured
}

// Where each thread's block starts, the pairs that cross blocks (phase A of evaluate_forces_of)
// and the ones each block takes from earlier blocks: fixed between two builds.
void Simulation::plan_pair_blocks(int threads) {
  PairBlocks& plan = pair_blocks_;
  if (static_cast<int>(plan.share.size()) != threads + 1) {
    plan.share.resize(threads + 1);
    for (int t = 0; t <= threads; ++t) plan.share[t] = static_cast<double>(t) / threads;
  }
  plan.busy.assign(threads, {});
  plan.threads = threads;
  plan.body_start.resize(threads + 1);
  for (int t = 0; t <= threads; ++t) plan.body_start[t] = pair_block_start(t);
  plan.crossing.clear();
  plan.taken.clear();
  plan.taken_start.assign(1, 0);
  for (int t = 0; t < threads; ++t) {
    const Index e0 = bodies_.element_begin(plan.body_start[t]);
    const Index e1 = bodies_.element_begin(plan.body_start[t + 1]);
    const Index p0 = pairs_.row_start[e0];
    for (Index p = p0; p < pairs_.row_start[e1]; ++p)
      if (pairs_.second[p] >= e1) plan.crossing.push_back(p);
    for (Index e = e0; e < e1; ++e)
      for (Index k = pairs_.as_second_start[e]; k < pairs_.as_second_start[e + 1]; ++k) {
        if (pairs_.as_second_pair[k] >= p0) break;  // as_second lists are in pair order
        plan.taken.push_back(pairs_.as_second_pair[k]);
      }
    plan.taken_start.push_back(static_cast<Index>(plan.taken.size()));
  }
}

template <bool kPointBodies>
void Simulation::evaluate_forces_of() {
  constexpr Index kPairPrefetchDistance = 16;  // work-list entries
  const Index np = pairs_.size();
  const Index ne = elements_.size();
  const int blocks = team_size();
  if (static_cast<int>(pair_work_.size()) < blocks) pair_work_.resize(blocks);
  // The sums start from zero: gather_chunk zeroes them as it reads them, which spares a pass over
  // the elements.
  if (static_cast<Index>(element_force_.size()) != ne) {
    element_force_.assign(ne, Vec3::Zero());
    element_torque_.assign(ne, Vec3::Zero());
    row_damping_.assign(ne, 0.0);
    row_friction_.assign(ne, 0.0);
  }
  pair_damping_.resize(np);
  pair_friction_.resize(np);
  // Spheres only: element k is body k, and the pair sums go straight into the bodies' force and
  // torque (drift_and_kick zeroed them after its half kick), sparing a pass over a second pair
  // of arrays. Clumps sum per element; gather_chunk adds the pebbles' lever torques.
  Vec3* const force_sum = kPointBodies ? bodies_.force.data() : element_force_.data();
  Vec3* const torque_sum = kPointBodies ? bodies_.torque.data() : element_torque_.data();
  const Vec3 length = domain_.length();
  const double dt = dt_;
  prepare_gather();
  Index bad_pair = np;
#pragma omp parallel num_threads(blocks) if (blocks > 1) reduction(min : bad_pair)
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const PairBlocks& plan = team_plan();
    const double start = nt > 1 ? omp_get_wtime() : 0.0;
    double waited = 0.0;  // at the barrier between the phases
    const Index b0 = plan.body_start[t], b1 = plan.body_start[t + 1];
    const Index e0 = bodies_.element_begin(b0), e1 = bodies_.element_begin(b1);
    const Index p0 = pairs_.row_start[e0], p1 = pairs_.row_start[e1];
    // Energy is summed per row (the first element), in pair order, then over elements in
    // chunk order: the same sums on any thread count.
    ContactBatch batch;
    prefill_batch<kPointBodies>(batch);
    Index lane_pair[kContactBatch];
    const double max_overlap = settings_.guards.max_overlap_fraction;
    auto too_deep = [&](int lane) {
      return batch.overlap[lane] > max_overlap * std::min(batch.ra[lane], batch.rb[lane]);
    };
    // Adds pair p to the batch if it touches (and marks it active). An active pair that has
    // opened is left to the caller to release.
    auto load_if_touching = [&](Index p) __attribute__((always_inline)) {
      const Vec3 d = separation(p, length);
      const double d2 = d.squaredNorm();
      if (!overlapping(p, d2)) return false;
      load_lane<kPointBodies>(batch, batch.size, p, d, d2);
      lane_pair[batch.size++] = p;
      pair_active_[p] = 1;  // after the loads: a byte store may alias them all
      return true;
    };
    // Phase A: the pairs whose second element lies in a later block, computed and stored, an
    // equal share of them by each thread. On one thread there are none.
    auto store_batch = [&]() {
      compute_contacts(batch, dt, any_rolling_);
      for (int k = 0; k < batch.size; ++k) {
        const Index p = lane_pair[k];
        store_springs(batch, k, p);
        if (too_deep(k)) bad_pair = std::min(bad_pair, p);
        pair_damping_[p] = batch.dissipated_damping[k];
        pair_friction_[p] = batch.dissipated_friction[k];
        pair_force_[p] = Vec3(batch.fx[k], batch.fy[k], batch.fz[k]);
        pair_torque_first_[p] = Vec3(batch.tax[k], batch.tay[k], batch.taz[k]);
        pair_torque_second_[p] = Vec3(batch.tbx[k], batch.tby[k], batch.tbz[k]);
      }
      batch.size = 0;
    };
    const auto crossing = static_cast<Index>(plan.crossing.size());
    for (Index k = crossing * t / nt; k < crossing * (t + 1) / nt; ++k) {
      const Index p = plan.crossing[k];
      if (batch.size == kContactBatch) store_batch();
      if (load_if_touching(p)) continue;
      pair_damping_[p] = 0.0;
      pair_friction_[p] = pair_active_[p] ? release_pair(p, separation(p, length)) : 0.0;
    }
    if (batch.size > 0) store_batch();
    const double arrived = nt > 1 ? omp_get_wtime() : 0.0;
#pragma omp barrier
    if (nt > 1) waited = omp_get_wtime() - arrived;
    // Phase B: the stored pairs of earlier blocks, each element's in pair order.
    for (Index k = plan.taken_start[t]; k < plan.taken_start[t + 1]; ++k) {
      const Index p = plan.taken[k];
      if (!pair_active_[p]) continue;
      const Index e = pairs_.second[p];
      force_sum[e] += pair_force_[p];
      torque_sum[e] += pair_torque_second_[p];
    }
    // Phase B visits only the pairs that do something: stored ones, touching ones, and active
    // ones that open now. The rest (a third or more of a Verlet list) add nothing, and sorting
    // them out first in a loop without branches spares the pair loop a branch that the CPU
    // mispredicts about every other pair.
    std::vector<Index>& work = pair_work_[t];
    work.resize(p1 - p0);
    Index n_work = 0;
    for (Index p = p0; p < p1; ++p) {
      const bool touching = overlapping(p, separation(p, length).squaredNorm());
      work[n_work] = p;
      n_work += static_cast<Index>((pairs_.second[p] >= e1) | (pair_active_[p] != 0) | touching);
    }
    // Phase B, own rows in pair order: the touching pairs a batch at a time, then their sums
    // (with the stored pairs and the releases between them) in pair order.
    for (Index k0 = 0; k0 < n_work;) {
      Index k1 = k0;
      for (; k1 < n_work; ++k1) {
        const Index p = work[k1];
        if (pairs_.second[p] >= e1) continue;
        if (batch.size == kContactBatch) break;  // this pair starts the next batch
        if (k1 + kPairPrefetchDistance < n_work) {  // see gather_chunk's wall prefetch
          const Index ahead = work[k1 + kPairPrefetchDistance];
          __builtin_prefetch(&pair_spring_[ahead]);
          const Index body = kPointBodies ? pairs_.second[ahead] : elements_.body[pairs_.second[ahead]];
          __builtin_prefetch(&bodies_.velocity[body]);
          __builtin_prefetch(&bodies_.angular_velocity[body]);
        }
        load_if_touching(p);
      }
      if (batch.size > 0) compute_contacts(batch, dt, any_rolling_);
      int lane = 0;
      for (Index k = k0; k < k1; ++k) {
        const Index p = work[k];
        const Index i = pairs_.first[p], j = pairs_.second[p];
        if (j >= e1) {
          row_damping_[i] += pair_damping_[p];
          row_friction_[i] += pair_friction_[p];
          if (!pair_active_[p]) continue;
          force_sum[i] -= pair_force_[p];
          torque_sum[i] += pair_torque_first_[p];
          continue;
        }
        if (lane < batch.size && lane_pair[lane] == p) {
          store_springs(batch, lane, p);
          row_damping_[i] += batch.dissipated_damping[lane];
          row_friction_[i] += batch.dissipated_friction[lane];
          if (too_deep(lane)) bad_pair = std::min(bad_pair, p);
          const Vec3 f(batch.fx[lane], batch.fy[lane], batch.fz[lane]);
          force_sum[i] -= f;
          torque_sum[i] += Vec3(batch.tax[lane], batch.tay[lane], batch.taz[lane]);
          force_sum[j] += f;
          torque_sum[j] += Vec3(batch.tbx[lane], batch.tby[lane], batch.tbz[lane]);
          ++lane;
          continue;
        }
        row_friction_[i] += release_pair(p, separation(p, length));  // an active contact that opened
      }
      batch.size = 0;
      k0 = k1;
    }
    // The thread's bodies now have all their pair forces (no other thread sums into them, and
    // the stored pairs were taken above): it gathers and kicks them without waiting for the
    // others, which never read them again this step.
    for (Index c = b0 / kChunkSize; c < chunk_count(b1); ++c) gather_chunk<kPointBodies>(c);
    if (nt > 1) pair_blocks_.busy[t].seconds += omp_get_wtime() - start - waited;
  }
  for (const auto& acc : pair_chunk_energy_) {
    dissipated_damping_ += acc.damping;
    dissipated_friction_ += acc.friction;
  }
  if (bad_pair < np) {
    const Index i = pairs_.first[bad_pair], j = pairs_.second[bad_pair];
    fail(fmt::format("overlap between bodies {} and {} exceeds {} of the smaller radius "
                     "(stiffness too low for the load, or time step too large)",
                     elements_.body[i], elements_.body[j], settings_.guards.max_overlap_fraction),
         elements_.body[i]);
  }
  finish_gather();
}

// The per-chunk sums of gather_chunk, sized and zeroed, and the walls rescanned when they moved.
void Simulation::prepare_gather() {
  const Index chunks = chunk_count(bodies_.size());
  const std::size_t nw = walls_.size(), nx = boxes_.size();
  pair_chunk_energy_.assign(chunks, ChunkEnergy{});
  body_chunk_energy_.assign(chunks, ChunkEnergy{});
  chunk_wall_force_.assign(chunks * nw, Vec3::Zero());
  chunk_box_face_force_.assign(chunks * nx, zero_faces());
  for (std::size_t w = 0; w < nw && !scan_walls_; ++w)
    scan_walls_ = (walls_[w].point - wall_scan_point_[w]).squaredNorm() > 0.0625 * skin_ * skin_ ||
                  walls_[w].normal != wall_scan_normal_[w];
  if (scan_walls_) scan_walls();
}

// Chunk c of the bodies once their pair forces are summed: the energy of their elements' pair
// rows, then walls, boxes, gravity, local damping and the second half kick.
// kPointBodies: every body is a sphere, element b is body b at its centre (no lever torque),
// and the pair loop summed straight into the bodies' force and torque.
template <bool kPointBodies>
void Simulation::gather_chunk(Index c) {
  constexpr Index kWallPrefetchDistance = 16;  // elements
  const Index nb = bodies_.size();
  const Index ne = elements_.size();
  const std::size_t nw = walls_.size();
  const std::size_t nx = boxes_.size();
  const double dt = dt_;
  const double half = 0.5 * dt_;
  const bool kick_now = gather_and_kick_;
  const Vec3 gravity = settings_.gravity;
  const double overlap_limit = settings_.guards.max_overlap_fraction;
  {  // the rows' energy, in element order: the same sums on any thread count
    ChunkEnergy rows;
    const Index end = bodies_.element_begin(chunk_end(c, nb));
    for (Index e = bodies_.element_begin(chunk_begin(c)); e < end; ++e) {
      rows.damping += row_damping_[e];
      rows.friction += row_friction_[e];
      row_damping_[e] = 0.0;
      row_friction_[e] = 0.0;
    }
    pair_chunk_energy_[c] = rows;
  }
  {
    ChunkEnergy acc;
    Vec3* wall_sum = nw ? &chunk_wall_force_[c * nw] : nullptr;
    const Index end = chunk_end(c, nb);
    for (Index b = chunk_begin(c); b < end; ++b) {
      const double mass = bodies_.mass[b];
      const Vec3& xb = bodies_.position[b];
      const Vec3& vb = bodies_.velocity[b];
      const Vec3& wb = bodies_.angular_velocity[b];
      Vec3 force = mass * gravity;
      Vec3 torque = Vec3::Zero();
      const Index e_end = bodies_.element_end(b);
      for (Index e = bodies_.element_begin(b); e < e_end; ++e) {
        // The wall springs of an element a few ahead are fetched now: few elements touch walls,
        // far apart in the array, so the hardware does not foresee them and each one's history
        // would otherwise be a wait for memory (measured 6 % of a sphere bed's step).
        if (const Index ahead = e + kWallPrefetchDistance; nw > 0 && ahead < ne && near_wall_[ahead])
          for (std::size_t w = 0; w < nw; ++w)
            if (wall_active_[ahead * nw + w]) __builtin_prefetch(&wall_history_[ahead * nw + w]);
        // The pair sums (see evaluate_forces_of), zeroed as read: the next step's pair loop sums from zero.
        Vec3 fe, te;
        if (kPointBodies) {
          fe = bodies_.force[b];
          te = bodies_.torque[b];
        } else {
          fe = element_force_[e];
          te = element_torque_[e];
          element_force_[e] = Vec3::Zero();
          element_torque_[e] = Vec3::Zero();
        }
        const double re = elements_.radius[e];
        const Vec3& xe = elements_.position[e];
        const std::size_t nw_e = near_wall_[e] ? nw : 0;  // see scan_walls
        for (std::size_t w = 0; w < nw_e; ++w) {
          const PlaneWall& wall = walls_[w];
          const double gap = (xe - wall.point).dot(wall.normal);
          // Most elements touch no wall: test the flag before touching the 56-byte history.
          std::uint8_t& active = wall_active_[e * nw + w];
          if (gap >= re && !active) continue;
          ContactHistory& history = wall_history_[e * nw + w];
          if (gap >= re) {
            active = 0;
            if (history.shear_force.squaredNorm() + history.rolling_moment.squaredNorm() > 0.0) {
              const Vec3& n = wall.normal;
              const Vec3 v = vb + wb.cross(xe - xb - re * n) - wall.velocity;
              acc.friction += released_spring_energy(
                  materials_.pair(wall.material, elements_.material[e]), history, re,
                  v - v.dot(n) * n, wb - wb.dot(n) * n, dt);
            }
            history = ContactHistory{};
            continue;
          }
          active = 1;
          // The wall is body a, the element body b: n points from the wall into the domain.
          ContactGeometry g;
          g.normal = wall.normal;
          g.overlap = re - gap;
          if (g.overlap > overlap_limit * re && acc.bad_body < 0) acc.bad_body = b;
          const Vec3 arm = -(re - 0.5 * g.overlap) * g.normal;
          g.relative_velocity = vb + wb.cross(xe - xb + arm) - wall.velocity;
          g.relative_spin = wb;
          g.frame_spin = 0.0;  // the wall fixes the contact frame
          const PairParameters& pp = materials_.pair(wall.material, elements_.material[e]);
          g.damping = damping_coefficient(pp.damping_ratio, mass, pp.normal_stiffness);
          g.rolling_radius = re;
          const ContactOutcome out = evaluate_contact(pp, g, history, dt);
          fe += out.force;
          te += arm.cross(out.force) + out.rolling_moment;
          wall_sum[w] -= out.force;
          acc.damping += out.dissipated_damping;
          acc.friction += out.dissipated_friction;
          acc.wall_work += out.force.dot(wall.velocity) * dt;
        }
        for (std::size_t k = 0; k < nx; ++k) {
          const RigidBox& box = boxes_[k];
          std::uint8_t& active = box_active_[e * nx + k];
          ContactHistory& history = box_history_[e * nx + k];
          const auto contact = sphere_box_contact(xe, re, box.centre, box.half_extent);
          if (!contact) {
            if (active) {
              active = 0;
              // As for walls: the springs' energy goes to friction when the contact opens.
              const Vec3 nearest = box.centre + (xe - box.centre).cwiseMax(-box.half_extent).cwiseMin(box.half_extent);
              const Vec3 n = (xe - nearest).normalized();
              const Vec3 v = vb + wb.cross(xe - xb - re * n) - box.velocity - box_growth_velocity(box, xe);
              acc.friction += released_spring_energy(materials_.pair(box.material, elements_.material[e]),
                                                     history, re, v - v.dot(n) * n, wb - wb.dot(n) * n, dt);
              history = ContactHistory{};
            }
            continue;
          }
          active = 1;
          // The box is body a, the element body b.
          ContactGeometry g;
          g.normal = contact->normal;
          g.overlap = contact->overlap;
          if (g.overlap > overlap_limit * re && acc.bad_body < 0) acc.bad_body = b;
          const Vec3 arm = -(re - 0.5 * g.overlap) * g.normal;
          const Vec3 growth = box_growth_velocity(box, xe);
          g.relative_velocity = vb + wb.cross(xe - xb + arm) - box.velocity - growth;
          g.relative_spin = wb;
          g.frame_spin = 0.0;
          const PairParameters& pp = materials_.pair(box.material, elements_.material[e]);
          g.damping = damping_coefficient(pp.damping_ratio, mass * box.mass / (mass + box.mass), pp.normal_stiffness);
          g.rolling_radius = re;
          const ContactOutcome out = evaluate_contact(pp, g, history, dt);
          fe += out.force;
          te += arm.cross(out.force) + out.rolling_moment;
          chunk_box_face_force_[c * nx + k][box_face(g.normal)] -= out.force;
          acc.damping += out.dissipated_damping;
          acc.friction += out.dissipated_friction;
          // Work of the drive: only driven axes put energy in; free axes trade kinetic energy.
          for (int a = 0; a < 3; ++a)
            if (box.driven[a]) acc.wall_work += out.force[a] * box.velocity[a] * dt;
          acc.wall_work += out.force.dot(growth) * dt;
        }
        force += fe;
        torque += kPointBodies ? te : Vec3(te + (xe - xb).cross(fe));
      }
      // PFC local damping: each component of force and moment loses alpha |F| against the
      // motion.
      bodies_.unbalanced_force[b] = force;
      const double alpha = bodies_.local_damping[b];
      if (alpha > 0.0) {
        for (int a = 0; a < 3; ++a) {
          const double df = alpha * std::abs(force[a]) * (vb[a] > 0 ? 1.0 : vb[a] < 0 ? -1.0 : 0.0);
          force[a] -= df;
          acc.local += df * vb[a] * dt;
          const double dm = alpha * std::abs(torque[a]) * (wb[a] > 0 ? 1.0 : wb[a] < 0 ? -1.0 : 0.0);
          torque[a] -= dm;
          acc.local += dm * wb[a] * dt;
        }
      }
      bodies_.force[b] = force;
      bodies_.torque[b] = torque;
      if (kick_now) kick(b, force, torque, half);
      // The state was finite at the drift (drift_and_kick checked it): the kick keeps it so
      // unless the force or torque is not finite, which is the cheaper test (it does not wait
      // for the kick's divisions).
      if (acc.bad_body < 0 && !std::isfinite((force + torque).sum())) acc.bad_body = b;
    }
    body_chunk_energy_[c] = acc;
  }
}

// The chunks' wall and box forces and energies summed in chunk order, and the gather's guards.
void Simulation::finish_gather() {
  const Index chunks = chunk_count(bodies_.size());
  const std::size_t nw = walls_.size(), nx = boxes_.size();
  const double overlap_limit = settings_.guards.max_overlap_fraction;
  for (std::size_t w = 0; w < nw; ++w) {
    Vec3 sum = Vec3::Zero();
    for (Index c = 0; c < chunks; ++c) sum += chunk_wall_force_[c * nw + w];
    wall_force_[w] = sum;
  }
  // Per face in chunk order, then the faces in face order: the same sums on any thread count.
  for (std::size_t k = 0; k < nx; ++k) {
    BoxFaceForces faces = zero_faces();
    for (Index c = 0; c < chunks; ++c)
      for (int f = 0; f < kBoxFaces; ++f) faces[f] += chunk_box_face_force_[c * nx + k][f];
    Vec3 sum = Vec3::Zero();
    for (const Vec3& f : faces) sum += f;
    box_face_force_[k] = faces;
    box_force_[k] = sum;
  }
  for (const auto& acc : body_chunk_energy_) {
    dissipated_damping_ += acc.damping;
    dissipated_friction_ += acc.friction;
    dissipated_local_ += acc.local;
    work_by_walls_ += acc.wall_work;
    if (acc.bad_body >= 0) {
      const Index b = acc.bad_body;
      if (!finite_state(bodies_.position[b], bodies_.velocity[b], bodies_.angular_velocity[b]))
        fail(fmt::format("body {} has a non-finite position or velocity", b), b);
      fail(fmt::format("body {} overlaps a wall by more than {} of its radius", b, overlap_limit), b);
    }
  }
}

void Simulation::check_stability() {
  const EnergyReport e = energy();
  energy_scale_ = std::max(energy_scale_, e.kinetic() + e.elastic);
  const double growth = e.total() - energy_reference_;
  if (growth > settings_.guards.energy_growth * energy_scale_) {
    // Name the fastest body: that is where the blow-up is.
    Index fastest = 0;
    double vmax = -1.0;
    for (Index b = 0; b < bodies_.size(); ++b) {
      const double v = bodies_.velocity[b].squaredNorm();
      if (v > vmax) vmax = v, fastest = b;
    }
    fail(fmt::format("energy grew by {:.4g} J with no work put in (allowed {:.4g} J); fastest is "
                     "body {} at {:.4g} m/s: the time step is too large for the stiffest "
                     "contact",
                     growth, settings_.guards.energy_growth * energy_scale_, fastest,
                     std::sqrt(vmax)),
         fastest, true);
  }
  last_good_ = snapshot();
}

void Simulation::fail(const std::string& what, Index body, bool step_completed) const {
  throw StabilityError(fmt::format("unstable run at t = {:.6g} s (step {}), body {}: {}. The "
                                   "last good state (t = {:.6g} s) is kept.",
                                   step_completed ? time_ : time_ + dt_,
                                   step_completed ? step_count_ : step_count_ + 1, body, what,
                                   last_good_ ? last_good_->time : 0.0));
}

EnergyReport Simulation::energy() const {
  EnergyReport r;
  const Index nb = bodies_.size();
  for (Index b = 0; b < nb; ++b) {
    const double m = bodies_.mass[b];
    r.kinetic_translational += 0.5 * m * bodies_.velocity[b].squaredNorm();
    const Vec3 w_body = bodies_.orientation[b].conjugate() * bodies_.angular_velocity[b];
    r.kinetic_rotational += 0.5 * w_body.dot(bodies_.inertia[b].cwiseProduct(w_body));
    r.gravitational -= m * settings_.gravity.dot(bodies_.position[b] - wrap_total_[b]);
  }
  const Vec3 length = domain_.length();
  for (Index p = 0; p < pairs_.size(); ++p) {
    if (!pair_active_[p]) continue;
    const Index i = pairs_.first[p], j = pairs_.second[p];
    const Vec3 d = elements_.position[j] + image_shift(pairs_.image[p], length) - elements_.position[i];
    const double overlap = elements_.radius[i] + elements_.radius[j] - d.norm();
    const PairParameters& pp = materials_.pair(elements_.material[i], elements_.material[j]);
    const double rbar = elements_.radius[i] * elements_.radius[j] /
                        (elements_.radius[i] + elements_.radius[j]);
    r.elastic += 0.5 * pp.normal_stiffness * std::max(0.0, overlap) * std::max(0.0, overlap);
    r.elastic += pair_spring_[p].shear_force.squaredNorm() / (2.0 * pp.shear_stiffness);
    if (pp.rolling_friction > 0.0)
      r.elastic += pair_rolling_[p].squaredNorm() /
                   (2.0 * pp.shear_stiffness * rbar * rbar);
  }
  const std::size_t nw = walls_.size();
  for (Index e = 0; e < elements_.size(); ++e) {
    for (std::size_t w = 0; w < nw; ++w) {
      const PlaneWall& wall = walls_[w];
      const double overlap = elements_.radius[e] - (elements_.position[e] - wall.point).dot(wall.normal);
      if (overlap <= 0.0) continue;
      const PairParameters& pp = materials_.pair(wall.material, elements_.material[e]);
      const ContactHistory& h = wall_history_[e * nw + w];
      const double re = elements_.radius[e];
      r.elastic += 0.5 * pp.normal_stiffness * overlap * overlap;
      r.elastic += h.shear_force.squaredNorm() / (2.0 * pp.shear_stiffness);
      if (pp.rolling_friction > 0.0)
        r.elastic += h.rolling_moment.squaredNorm() / (2.0 * pp.shear_stiffness * re * re);
    }
  }
  for (std::size_t k = 0; k < boxes_.size(); ++k) {
    const RigidBox& box = boxes_[k];
    for (int a = 0; a < 3; ++a) {
      if (box.driven[a]) continue;
      r.kinetic_translational += 0.5 * box.mass * box.velocity[a] * box.velocity[a];
      r.gravitational -= box.mass * settings_.gravity[a] * box.centre[a];
    }
    for (Index e = 0; e < elements_.size(); ++e) {
      if (!box_active_[e * boxes_.size() + k]) continue;
      const auto contact = sphere_box_contact(elements_.position[e], elements_.radius[e], box.centre, box.half_extent);
      if (!contact) continue;
      const PairParameters& pp = materials_.pair(box.material, elements_.material[e]);
      const ContactHistory& h = box_history_[e * boxes_.size() + k];
      const double re = elements_.radius[e];
      r.elastic += 0.5 * pp.normal_stiffness * contact->overlap * contact->overlap;
      r.elastic += h.shear_force.squaredNorm() / (2.0 * pp.shear_stiffness);
      if (pp.rolling_friction > 0.0)
        r.elastic += h.rolling_moment.squaredNorm() / (2.0 * pp.shear_stiffness * re * re);
    }
  }
  r.dissipated_damping = dissipated_damping_;
  r.dissipated_friction = dissipated_friction_;
  r.dissipated_local = dissipated_local_;
  r.work_by_walls = work_by_walls_;
  return r;
}

Index Simulation::active_contact_count() const {
  Index n = 0;
  for (auto a : pair_active_) n += a;
  const std::size_t nw = walls_.size();
  for (Index e = 0; e < elements_.size(); ++e)
    for (std::size_t w = 0; w < nw; ++w)
      if (elements_.radius[e] > (elements_.position[e] - walls_[w].point).dot(walls_[w].normal)) ++n;
  return n;
}

// The force of active pair p on its second element, as the last step left it: Fn n + Fs, with
// Fn = kn d - (kn d - Fn) from the spring's history; the pair loop keeps no copy of it.
Vec3 Simulation::contact_force(Index p, const Vec3& d) const {
  const Index i = pairs_.first[p], j = pairs_.second[p];
  const double r = d.norm();
  const double overlap = elements_.radius[i] + elements_.radius[j] - r;
  const double kn = materials_.pair(elements_.material[i], elements_.material[j]).normal_stiffness;
  const PairSpring& h = pair_spring_[p];
  return (kn * overlap - h.damping_force) * (d / r) + h.shear_force;
}

ContactHistory Simulation::pair_history(Index p) const {
  return ContactHistory{pair_spring_[p].shear_force, pair_rolling_[p], pair_spring_[p].damping_force};
}

void Simulation::set_pair_history(Index p, const ContactHistory& h) {
  pair_spring_[p] = PairSpring{h.shear_force, h.damping_force};
  pair_rolling_[p] = h.rolling_moment;
}

double Simulation::unbalanced_force_ratio() const {
  const Vec3 length = domain_.length();
  double unbalanced = 0.0, contact = 0.0;
  Index contacts = 0;
  for (Index b = 0; b < bodies_.size(); ++b) unbalanced += bodies_.unbalanced_force[b].norm();
  for (Index p = 0; p < pairs_.size(); ++p) {
    if (!pair_active_[p]) continue;
    contact += contact_force(p, separation(p, length)).norm();
    ++contacts;
  }
  if (contacts == 0 || contact == 0.0) return std::numeric_limits<double>::infinity();
  return (unbalanced / std::max<Index>(bodies_.size(), 1)) / (contact / contacts);
}

std::vector<ContactRecord> Simulation::contacts() const {
  std::vector<ContactRecord> out;
  const Vec3 length = domain_.length();
  for (Index p = 0; p < pairs_.size(); ++p) {
    if (!pair_active_[p]) continue;
    const Index i = pairs_.first[p], j = pairs_.second[p];
    const Vec3 d = separation(p, length);
    const double r = d.norm();
    const double overlap = elements_.radius[i] + elements_.radius[j] - r;
    ContactRecord c;
    c.body_a = elements_.body[i];
    c.body_b = elements_.body[j];
    c.point = elements_.position[i] + (elements_.radius[i] - 0.5 * overlap) * (d / r);
    c.force = contact_force(p, d);
    c.overlap = overlap;
    out.push_back(c);
  }
  return out;
}

}  // namespace mfdem::dem
