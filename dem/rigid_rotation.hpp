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
//
// Cost: each axis rotation needs the sine and cosine of one half angle only (the full angle's
// follow from the double-angle formulas), and the quaternion is normalised once per step, not
// once per axis. Half angles of a DEM step are tiny (|w| dt / 2 ~ 1e-4 rad), where a short
// Taylor series is exact to round-off and far cheaper than the library's sincos.
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

// Below this |x| (rad) the series of cos x to x^10 and sin x to x^9 are exact in double
// precision: the first dropped terms, x^12/12! and x^11/11!, are below 2.5e-18 of the values.
inline constexpr double kSeriesHalfAngle = 0.1;

// cos x and sin x.
[[gnu::always_inline]] inline void cos_sin(double x, double& c, double& s) {
  if (std::abs(x) > kSeriesHalfAngle) {
    c = std::cos(x);
    s = std::sin(x);
    return;
  }
  const double x2 = x * x;
  // Horner forms of the Taylor series; coefficients 1/n!.
  c = 1.0 - x2 * (1.0 / 2 - x2 * (1.0 / 24 - x2 * (1.0 / 720 - x2 * (1.0 / 40320 - x2 * (1.0 / 3628800)))));
  s = x * (1.0 - x2 * (1.0 / 6 - x2 * (1.0 / 120 - x2 * (1.0 / 5040 - x2 * (1.0 / 362880)))));
}

// Exact free rotation about principal axis k for time h; q is left unnormalised.
[[gnu::always_inline]] inline void rotate_about_axis(Quat& q, Vec3& l_body, const Vec3& inertia, int k,
                                                     double h) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  double ch, sh;  // cos, sin of half the angle
  cos_sin(0.5 * h * l_body[k] / inertia[k], ch, sh);
  // The body turns by +angle about axis k; a fixed world vector seen from the body turns by
  // -angle: l_i' = c l_i + s l_j, l_j' = c l_j - s l_i.
  const double c = (ch - sh) * (ch + sh), s = 2.0 * sh * ch;
  const double li = l_body[i], lj = l_body[j];
  l_body[i] = c * li + s * lj;
  l_body[j] = c * lj - s * li;
  // q <- q (cos, sin e_k): the quaternion product written out for a unit axis.
  auto& v = q.coeffs();  // x, y, z, w
  const double w = v[3], vk = v[k], vi = v[i], vj = v[j];
  v[3] = ch * w - sh * vk;
  v[k] = ch * vk + sh * w;
  v[i] = ch * vi + sh * vj;
  v[j] = ch * vj - sh * vi;
}

// Free rotation over dt.
inline void free_rotation(Quat& q, Vec3& l_body, const Vec3& inertia, double dt) {
  rotate_about_axis(q, l_body, inertia, 2, 0.5 * dt);
  rotate_about_axis(q, l_body, inertia, 1, 0.5 * dt);
  rotate_about_axis(q, l_body, inertia, 0, dt);
  rotate_about_axis(q, l_body, inertia, 1, 0.5 * dt);
  rotate_about_axis(q, l_body, inertia, 2, 0.5 * dt);
  q.normalize();
}

}  // namespace mfdem::dem
