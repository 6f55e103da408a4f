// Simulation: one velocity-Verlet step (drift, neighbour list, forces, kick) and the stability checks.
#include "dem/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "dem/rigid_rotation.hpp"

namespace mfdem::dem {

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
  if (!pending_radius_.empty()) apply_pending_radii();
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
  // The first force evaluation (prepare) sees the bodies as they were given.
  if (!gather_and_kick_) throw InitialOverlapError(fmt::format("the bodies as given, before any step: {}", what));
  throw StabilityError(fmt::format("unstable run at t = {:.6g} s (step {}), body {}: {}. The "
                                   "last good state (t = {:.6g} s) is kept.",
                                   step_completed ? time_ : time_ + dt_,
                                   step_completed ? step_count_ : step_count_ + 1, body, what,
                                   last_good_ ? last_good_->time : 0.0));
}

}  // namespace mfdem::dem
