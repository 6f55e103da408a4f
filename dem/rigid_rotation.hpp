#pragma once
// Rotation of a rigid body with a full (principal) inertia tensor.
//
// Free rotation over a step is split into exact rotations about the principal axes,
//   R3(dt/2) R2(dt/2) R1(dt) R2(dt/2) R3(dt/2),
// each turning the orientation and the body-frame angular momentum together. The scheme is
// symplectic and time-reversible and keeps the world angular momentum of a torque-free body
// exactly (up to round-off): Dullweber, Leimkuhler & McLachlan (1997), "Symplectic splitting
// methods for rigid body molecular dynamics", J. Chem. Phys. 107, 5840, doi:10.1063/1.474310.
// Torques enter as half kicks of the angular momentum around it (velocity Verlet).
#include <cmath>

#include "dem/types.hpp"

namespace mfdem::dem {

// Angular momentum in the body frame from the world angular velocity, kg m^2/s.
inline Vec3 body_angular_momentum(const Quat& q, const Vec3& inertia, const Vec3& omega_world) {
  return inertia.cwiseProduct(q.conjugate() * omega_world);
}

inline Vec3 world_angular_velocity(const Quat& q, const Vec3& inertia, const Vec3& l_body) {
  return q * l_body.cwiseQuotient(inertia);
}

// Exact free rotation about principal axis k for time h.
inline void rotate_about_axis(Quat& q, Vec3& l_body, const Vec3& inertia, int k, double h) {
  const double angle = h * l_body[k] / inertia[k];
  const Eigen::AngleAxisd turn(angle, Vec3::Unit(k));
  // The body turns by +angle; a fixed world vector seen from the body turns by -angle.
  l_body = turn.inverse() * l_body;
  q = (q * Quat(turn)).normalized();
}

// Free rotation over dt.
inline void free_rotation(Quat& q, Vec3& l_body, const Vec3& inertia, double dt) {
  rotate_about_axis(q, l_body, inertia, 2, 0.5 * dt);
  rotate_about_axis(q, l_body, inertia, 1, 0.5 * dt);
  rotate_about_axis(q, l_body, inertia, 0, dt);
  rotate_about_axis(q, l_body, inertia, 1, 0.5 * dt);
  rotate_about_axis(q, l_body, inertia, 2, 0.5 * dt);
}

}  // namespace mfdem::dem
