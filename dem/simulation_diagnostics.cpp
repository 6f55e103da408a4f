// Simulation: energy balance, contact lists and the unbalanced force ratio, read off the state.
#include "dem/simulation.hpp"

#include <algorithm>
#include <cmath>

namespace mfdem::dem {

double Simulation::pair_elastic_energy(Index p) const {
  const Index i = pairs_.first[p], j = pairs_.second[p];
  const Vec3 d = elements_.position[j] + image_shift(pairs_.image[p], domain_.length()) - elements_.position[i];
  const double overlap = std::max(0.0, elements_.radius[i] + elements_.radius[j] - d.norm());
  const PairParameters& pp = materials_.pair(elements_.material[i], elements_.material[j]);
  const double rbar = elements_.radius[i] * elements_.radius[j] / (elements_.radius[i] + elements_.radius[j]);
  double energy = 0.5 * pp.normal_stiffness * overlap * overlap;
  energy += pair_spring_[p].shear_force.squaredNorm() / (2.0 * pp.shear_stiffness);
  if (pp.rolling_friction > 0.0) energy += pair_rolling_[p].squaredNorm() / (2.0 * pp.shear_stiffness * rbar * rbar);
  return energy;
}

double Simulation::wall_elastic_energy(Index e, std::size_t w) const {
  const PlaneWall& wall = walls_[w];
  const double overlap = elements_.radius[e] - (elements_.position[e] - wall.point).dot(wall.normal);
  if (overlap <= 0.0) return 0.0;
  const PairParameters& pp = materials_.pair(wall.material, elements_.material[e]);
  const ContactHistory& h = wall_history_[e * walls_.size() + w];
  const double re = elements_.radius[e];
  double energy = 0.5 * pp.normal_stiffness * overlap * overlap;
  energy += h.shear_force.squaredNorm() / (2.0 * pp.shear_stiffness);
  if (pp.rolling_friction > 0.0) energy += h.rolling_moment.squaredNorm() / (2.0 * pp.shear_stiffness * re * re);
  return energy;
}

double Simulation::box_elastic_energy(Index e, std::size_t k) const {
  if (!box_active_[e * boxes_.size() + k]) return 0.0;
  const RigidBox& box = boxes_[k];
  const auto contact =
      sphere_box_contact(box_image(elements_.position[e], box), elements_.radius[e], box.centre, box.half_extent);
  if (!contact) return 0.0;
  const PairParameters& pp = materials_.pair(box.material, elements_.material[e]);
  const ContactHistory& h = box_history_[e * boxes_.size() + k];
  const double re = elements_.radius[e];
  double energy = 0.5 * pp.normal_stiffness * contact->overlap * contact->overlap;
  energy += h.shear_force.squaredNorm() / (2.0 * pp.shear_stiffness);
  if (pp.rolling_friction > 0.0) energy += h.rolling_moment.squaredNorm() / (2.0 * pp.shear_stiffness * re * re);
  return energy;
}

double Simulation::element_elastic_energy(Index e) const {
  double energy = 0.0;
  for_each_pair_of(e, [&](Index p) {
    if (pair_active_[p]) energy += pair_elastic_energy(p);
  });
  for (std::size_t w = 0; w < walls_.size(); ++w) energy += wall_elastic_energy(e, w);
  for (std::size_t k = 0; k < boxes_.size(); ++k) energy += box_elastic_energy(e, k);
  return energy;
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
  for (Index p = 0; p < pairs_.size(); ++p)
    if (pair_active_[p]) r.elastic += pair_elastic_energy(p);
  const std::size_t nw = walls_.size();
  for (Index e = 0; e < elements_.size(); ++e)
    for (std::size_t w = 0; w < nw; ++w) r.elastic += wall_elastic_energy(e, w);
  for (std::size_t k = 0; k < boxes_.size(); ++k) {
    const RigidBox& box = boxes_[k];
    for (int a = 0; a < 3; ++a) {
      if (box.driven[a]) continue;
      r.kinetic_translational += 0.5 * box.mass * box.velocity[a] * box.velocity[a];
      r.gravitational -= box.mass * settings_.gravity[a] * box.centre[a];
    }
    for (Index e = 0; e < elements_.size(); ++e) r.elastic += box_elastic_energy(e, k);
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
