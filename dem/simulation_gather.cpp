// Simulation: the forces gathered onto the bodies in chunks, walls and boxes, and the second half kick.
#include "dem/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "dem/chunked.hpp"

namespace mfdem::dem {

// The per-chunk sums of gather_chunk, sized and zeroed, and the walls rescanned when they moved.
void Simulation::prepare_gather() {
  const Index chunks = chunk_count(bodies_.size());
  const std::size_t nw = walls_.size(), nx = boxes_.size();
  pair_chunk_energy_.assign(chunks, ChunkEnergy{});
  body_chunk_energy_.assign(chunks, ChunkEnergy{});
  chunk_wall_force_.assign(chunks * nw, Vec3::Zero());
  chunk_box_face_force_.assign(chunks * nx, zero_box_faces());
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
          const Vec3 xi = box_image(xe, box);  // the element as the box sees it
          const auto contact = sphere_box_contact(xi, re, box.centre, box.half_extent);
          if (!contact) {
            if (active) {
              active = 0;
              // As for walls: the springs' energy goes to friction when the contact opens.
              const Vec3 nearest = box.centre + (xi - box.centre).cwiseMax(-box.half_extent).cwiseMin(box.half_extent);
              const Vec3 n = (xi - nearest).normalized();
              const Vec3 v = vb + wb.cross(xe - xb - re * n) - box.velocity - box_growth_velocity(box, xi);
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
          const Vec3 growth = box_growth_velocity(box, xi);
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

// Both forms, for the pair loop in simulation_pair_forces.cpp: spheres only, and clumps.
template void Simulation::gather_chunk<true>(Index);
template void Simulation::gather_chunk<false>(Index);

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
    BoxFaceForces faces = zero_box_faces();
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

}  // namespace mfdem::dem
