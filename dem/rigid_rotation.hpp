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

// Below this |x| (rad) the series of cos x to x^4 and sin x to x^5 are exact in double
// precision: the first dropped terms, x^6/6! and x^7/7!, are below 1.4e-21 and 2e-22 of the
// values. A DEM step's half angles are far smaller (1e-4 rad needs |w| = 20 rad/s at dt = 1e-5
// s); beyond it the library's sin and cos take over.
inline constexpr double kSeriesHalfAngle = 1e-3;

// cos x and sin x. The short series keeps the chain of dependent operations of a step's five
// axis rotations short: each rotation needs the angular momentum the one before left.
[[gnu::always_inline]] inline void cos_sin(double x, double& c, double& s) {
  if (std::abs(x) > kSeriesHalfAngle) {
    c = std::cos(x);
    s = std::sin(x);
    return;
  }
  const double x2 = x * x;
  // Horner forms of the Taylor series; coefficients 1/n!.
  c = 1.0 - x2 * (1.0 / 2 - x2 * (1.0 / 24));
  s = x - x * x2 * (1.0 / 6 - x2 * (1.0 / 120));
}

// Exact free rotation about principal axis k for time h; q is left unnormalised.
// inverse_inertia: 1/I per principal axis.
[[gnu::always_inline]] inline void rotate_about_axis(Quat& q, Vec3& l_body, const Vec3& inverse_inertia,
                                                     int k, double h) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  double ch, sh;  // cos, sin of half the angle
  cos_sin(0.5 * h * inverse_inertia[k] * l_body[k], ch, sh);
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

// Free rotation of N bodies over dt, side by side. Each body's rotations form one long chain of
// dependent operations (every axis rotation needs the angular momentum the one before left);
// interleaving independent bodies lets the CPU overlap their chains. Each body's arithmetic is
// that of a lone free_rotation.
template <int N>
[[gnu::always_inline]] inline void free_rotations(Quat* const q[N], Vec3 l_body[N], const Vec3* const inertia[N],
                                                  double dt) {
  Vec3 inverse[N];  // divisions once, off the chains
  for (int m = 0; m < N; ++m) inverse[m] = inertia[m]->cwiseInverse();
  auto turn = [&](int k, double h) {
    for (int m = 0; m < N; ++m) rotate_about_axis(*q[m], l_body[m], inverse[m], k, h);
  };
  turn(2, 0.5 * dt);
  turn(1, 0.5 * dt);
  turn(0, dt);
  turn(1, 0.5 * dt);
  turn(2, 0.5 * dt);
  for (int m = 0; m < N; ++m) q[m]->normalize();
}

// Free rotation over dt.
inline void free_rotation(Quat& q, Vec3& l_body, const Vec3& inertia, double dt) {
  Quat* const qs[1] = {&q};
  const Vec3* const inertias[1] = {&inertia};
  free_rotations<1>(qs, &l_body, inertias, dt);
}

}  // namespace mfdem::dem
