#pragma once
// Linear spring-dashpot contact with Coulomb friction and elastic-plastic rolling resistance.
//
// Sub-models, called in this order by evaluate_contact (as LAMMPS GranularModel does):
//   1. normal:     Fn = max(0, kn d - cn vn),  cn = 2 beta_n sqrt(m_eff kn)          [N]
//                  m_eff = m_a m_b / (m_a + m_b) (m_a against a wall)
//                  d overlap [m], vn = (v_b - v_a).n [m/s] (positive when separating);
//                  never tensile: the dashpot cannot pull (Hertz-free linear model).
//   2. tangential: Fs <- rotate(Fs) - ks vt dt,  |Fs| <= mu Fn                      [N]
//                  incremental spring; history turns with the contact frame.
//   3. rolling:    Mr <- rotate(Mr) - kr w_roll dt,  kr = ks Rbar^2,  |Mr| <= mu_r Rbar Fn [N m]
//                  Rbar = Ra Rb / (Ra + Rb) (= Ra against a wall); Ai, Pan, Ooi & Rahman (2011),
//                  "Assessment of rolling resistance models in DEM", Powder Technol. 206, 269-282,
//                  doi:10.1016/j.powtec.2010.09.030, model type C (PFC rrlinear) without the
//                  rolling dashpot.
// The normal model supplies the Coulomb limits mu Fn and mu_r Rbar Fn to the others.
// Conventions: n points from body a to body b; results are the force and moment acting on b;
// a receives the opposite force and moment (plus its own lever-arm torque).
#include <algorithm>
#include <cmath>

#include "dem/material.hpp"
#include "dem/types.hpp"

namespace mfdem::dem {

// Geometry and kinematics of one contact, computed by the caller.
struct ContactGeometry {
  double overlap = 0.0;         // d > 0, m
  Vec3 normal = Vec3::UnitZ();  // unit, from a to b
  Vec3 relative_velocity;       // velocity of b's surface minus a's at the contact point, m/s
  Vec3 relative_spin;           // omega_b - omega_a, rad/s
  double frame_spin = 0.0;      // (omega_a + omega_b)/2 . n: how fast the contact frame turns
                                // about the normal, rad/s
  double damping = 0.0;         // cn = damping_coefficient(beta_n, m_eff, kn), N s/m; the
                                // caller's, as a pair's is fixed (the neighbour list keeps it)
  double rolling_radius = 0.0;  // Rbar, m
};

// Springs carried from step to step.
struct ContactHistory {
  Vec3 shear_force = Vec3::Zero();     // Fs on b, N
  Vec3 rolling_moment = Vec3::Zero();  // Mr on b, N m
  double damping_force = 0.0;          // kn d - Fn of the last step, N (for the energy account)
};

struct ContactOutcome {
  Vec3 force = Vec3::Zero();           // total contact force on b, N
  Vec3 rolling_moment = Vec3::Zero();  // moment on b from rolling resistance, N m
  double normal_force = 0.0;           // Fn >= 0, N
  // Energy dissipated during this step, J.
  double dissipated_damping = 0.0;
  double dissipated_friction = 0.0;    // sliding and rolling slip
};

// --- stateless kernels --------------------------------------------------------------------

[[gnu::always_inline]] inline double damping_coefficient(double damping_ratio, double effective_mass, double kn) {
  return 2.0 * damping_ratio * std::sqrt(effective_mass * kn);
}

// Normal force magnitude; never tensile.
[[gnu::always_inline]] inline double normal_force(double kn, double cn, double overlap, double normal_velocity) {
  return std::max(0.0, kn * overlap - cn * normal_velocity);
}

// Carries a tangential vector (spring force or moment) from the previous contact frame to the
// current one: drop the component along the new normal, turn it about the normal by the pair's
// mean spin, and keep its magnitude (so a rigidly rotated contact keeps its force).
[[gnu::always_inline]] inline Vec3 rotate_to_frame(const Vec3& v, const Vec3& normal, double spin_about_normal,
                            double dt) {
  const double magnitude2 = v.squaredNorm();
  if (magnitude2 == 0.0) return v;
  const double along = v.dot(normal);
  const double turn = spin_about_normal * dt;
  Vec3 t = v - along * normal;
  t += turn * normal.cross(t);
  // |t|^2 = (|v|^2 - (v.n)^2)(1 + turn^2) (the turn adds n x t, normal to t and as long), known
  // without waiting for t: it shortens the kernel's longest chain of dependent operations. Where
  // v lies almost along n the difference cancels, and |t|^2 is summed instead.
  const double across2 = magnitude2 - along * along;
  const double t2 = across2 > 0.5 * magnitude2 ? across2 * (1.0 + turn * turn) : t.squaredNorm();
  if (t2 == 0.0) return Vec3::Zero();
  return t * std::sqrt(magnitude2 / t2);
}

// Elastic-plastic spring update: increment, then cap at `limit`. Returns the energy dissipated
// by the slip, J: the slip distance (|trial| - limit)/k times the mean of the force before and
// after the step along the slip (trapezoid rule). In steady sliding that is limit x slip; when
// the limit changes during sliding (an impact) the mean keeps the account second-order in dt,
// consistent with the velocity-Verlet work; limit x slip alone is off by O(dt), and misses the
// energy a stuck spring releases when the limit drops below it as a contact ends.
[[gnu::always_inline]] inline double spring_with_slip(Vec3& spring, const Vec3& rate, double stiffness, double dt,
                               double limit) {
  const Vec3 previous = spring;
  spring -= (stiffness * dt) * rate;
  // A stuck spring (most contacts of a packed bed) is told by its square: no square root on
  // the kernel's longest chain.
  const double magnitude2 = spring.squaredNorm();
  if (magnitude2 <= limit * limit || magnitude2 == 0.0) return 0.0;
  const double magnitude = std::sqrt(magnitude2);
  if (magnitude <= limit) return 0.0;  // limit^2 rounded below |spring|^2 by an ulp
  const double slip = (magnitude - limit) / stiffness;
  const double previous_along_slip = previous.dot(spring) / magnitude;
  spring *= limit / magnitude;
  return 0.5 * (limit + previous_along_slip) * slip;
}

// --- the composed law ---------------------------------------------------------------------

// Always inlined: it is the innermost call of the pair loop (measured 28 % of a bed's step as a call).
[[gnu::always_inline]] inline ContactOutcome evaluate_contact(const PairParameters& p, const ContactGeometry& g,
                                       ContactHistory& history, double dt) {
  ContactOutcome out;
  const Vec3& n = g.normal;
  const double vn = g.relative_velocity.dot(n);
  const double cn = g.damping;
  const double elastic = p.normal_stiffness * g.overlap;
  const double fn = normal_force(p.normal_stiffness, cn, g.overlap, vn);
  out.normal_force = fn;
  // Work of the dashpot: the part of Fn beyond the spring times the approach speed. vn is the
  // half-step velocity (t - dt/2), so the force is averaged over the step, (t - dt) and t,
  // which makes the sum over a contact second-order in dt (the force at t alone over-counts
  // by beta w0 dt of each impact's loss).
  out.dissipated_damping = 0.5 * ((elastic - fn) + history.damping_force) * vn * dt;
  history.damping_force = elastic - fn;

  const Vec3 vt = g.relative_velocity - vn * n;
  history.shear_force = rotate_to_frame(history.shear_force, n, g.frame_spin, dt);
  out.dissipated_friction =
      spring_with_slip(history.shear_force, vt, p.shear_stiffness, dt, p.friction * fn);

  if (p.rolling_friction > 0.0) {
    const double kr = p.shear_stiffness * g.rolling_radius * g.rolling_radius;
    const Vec3 w_roll = g.relative_spin - g.relative_spin.dot(n) * n;
    history.rolling_moment = rotate_to_frame(history.rolling_moment, n, g.frame_spin, dt);
    out.dissipated_friction += spring_with_slip(history.rolling_moment, w_roll, kr, dt,
                                                p.rolling_friction * g.rolling_radius * fn);
    out.rolling_moment = history.rolling_moment;
  }
  out.force = fn * n + history.shear_force;
  return out;
}

// Energy the tangential and rolling springs of a contact that has just opened give up to
// friction, J. The springs are discarded with the contact: in continuous time the Coulomb caps
// (mu Fn, mu_r Rbar Fn -> 0 with the overlap) slip them to zero just before it opens. Part of
// their energy has already gone into the motion: this step's first half kick applied the last
// spring force and moment over dt/2, at relative tangential velocity vt and rolling velocity
// w_roll (b relative to a). Without this account a contact that opens with a loaded spring
// (large mu or mu_r) loses energy that the balance never sees.
inline double released_spring_energy(const PairParameters& p, const ContactHistory& h, double rbar,
                                     const Vec3& vt, const Vec3& w_roll, double dt) {
  double e = h.shear_force.squaredNorm() / (2.0 * p.shear_stiffness) -
             0.5 * dt * h.shear_force.dot(vt);
  if (p.rolling_friction > 0.0)
    e += h.rolling_moment.squaredNorm() / (2.0 * p.shear_stiffness * rbar * rbar) -
         0.5 * dt * h.rolling_moment.dot(w_roll);
  return std::max(0.0, e);
}

}  // namespace mfdem::dem
