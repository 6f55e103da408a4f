// Simulation: the Verlet neighbour list, its skin, the wall scan and the release of opened contacts.
#include "dem/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dem/chunked.hpp"

namespace mfdem::dem {

// A pair left out of the list was at least r_i + r_j + skin apart at the build; it can touch
// once moves and growth of both add up to the skin: rebuild when move + growth > skin / 2.
void Simulation::maybe_rebuild() {
  if (radius_growth_ > 0.0) {
    const double budget = 0.5 * skin_ - radius_growth_;
    if (budget <= 0.0 || max_move2_ > budget * budget) rebuild();
    return;
  }
  if (4.0 * max_move2_ > skin_ * skin_) rebuild();
}

void Simulation::set_element_radius(Index e, double radius) {
  if (!prepared_) throw std::logic_error("set_element_radius: call prepare() first");
  if (e < 0 || e >= elements_.size())
    throw std::invalid_argument(fmt::format("element {} does not exist ({} elements)", e, elements_.size()));
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw std::invalid_argument(fmt::format("element {}: radius must be a positive finite number (got {})", e, radius));
  pending_radius_.emplace_back(e, radius);
}

// The new radii take effect between the drift and the force evaluation, as a time-dependent
// potential does in velocity Verlet, so that the step's forces see them. The work they do is the
// elastic energy they add at the new positions, plus half the change of the normal forces times
// the step's drift (1/2 dF . v dt): velocity Verlet's kinetic energy takes the new forces for the
// whole drift, and without that term the account drifts by about w dt of the work (first order).
void Simulation::apply_pending_radii() {
  const Vec3 length = domain_.length();
  for (const auto& [e, radius] : pending_radius_) {
    const double old_radius = elements_.radius[e];
    if (radius == old_radius) continue;
    const double before = element_elastic_energy(e);
    const Vec3& ve = bodies_.velocity[elements_.body[e]];
    double drift_work = 0.0;
    // The normal spring's change on e, kn (d_new - d_old) along n (n pointing into e), and the
    // drift velocity of e relative to the other side.
    const auto add = [&](double kn, double gap_old, double gap_new, const Vec3& n, const Vec3& other_velocity) {
      const double change = kn * (std::max(0.0, -gap_new) - std::max(0.0, -gap_old));
      drift_work += 0.5 * dt_ * change * n.dot(ve - other_velocity);
    };
    const auto pair = [&](Index p) {
      const Index i = pairs_.first[p], j = pairs_.second[p];
      const Vec3 d = separation(p, length);
      const double distance = d.norm();
      if (distance == 0.0) return;
      const Index other = i == e ? j : i;
      const Vec3 n = (i == e ? -d : d) / distance;  // from the other element into e
      const double kn = materials_.pair(elements_.material[i], elements_.material[j]).normal_stiffness;
      const double rest = elements_.radius[other];
      add(kn, distance - old_radius - rest, distance - radius - rest, n, bodies_.velocity[elements_.body[other]]);
    };
    for_each_pair_of(e, pair);
    for (const auto& wall : walls_) {
      const double gap = (elements_.position[e] - wall.point).dot(wall.normal);
      add(materials_.pair(wall.material, elements_.material[e]).normal_stiffness, gap - old_radius, gap - radius,
          wall.normal, wall.velocity);
    }
    for (const auto& box : boxes_) {
      const Vec3 x = box_image(elements_.position[e], box);
      const auto contact = sphere_box_contact(x, radius, box.centre, box.half_extent);
      if (!contact) continue;
      const double gap_new = -contact->overlap, gap_old = gap_new + (radius - old_radius);
      add(materials_.pair(box.material, elements_.material[e]).normal_stiffness, gap_old, gap_new, contact->normal,
          box.velocity);
    }
    elements_.radius[e] = radius;
    radius_growth_ = std::max(radius_growth_, radius - build_radius_[e]);
    largest_radius_ = std::max(largest_radius_, radius);
    for_each_pair_of(e, [&](Index p) { pair_reach2_[p] = reach2_of(p); });
    work_by_walls_ += element_elastic_energy(e) - before + drift_work;
  }
  pending_radius_.clear();
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
    pair_reach2_[p] = reach2_of(p);
    const double mi = bodies_.mass[elements_.body[i]], mj = bodies_.mass[elements_.body[j]];
    const PairParameters& pp = materials_.pair(elements_.material[i], elements_.material[j]);
    pair_dashpot_[p] = damping_coefficient(pp.damping_ratio, mi * mj / (mi + mj), pp.normal_stiffness);
  }
  build_position_ = elements_.position;
  build_radius_ = elements_.radius;
  radius_growth_ = 0.0;
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
// periodic axis allows (kPeriodicReaches x (largest diameter + skin)). The skin only decides how often
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
    if (domain_.periodic[a]) ceiling = std::min(ceiling, domain_.length()[a] / kPeriodicReaches - 2.0 * largest_radius_);
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

}  // namespace mfdem::dem
