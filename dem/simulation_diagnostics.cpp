// Simulation: energy balance, contact lists and the unbalanced force ratio, read off the state.
#include "dem/simulation.hpp"

#include <algorithm>
#include <cmath>

namespace mfdem::dem {

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
