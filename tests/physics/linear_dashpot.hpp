// Closed forms of one linear spring-dashpot impact whose force is never tensile, the normal law
// of dem/contact_law.hpp: F = max(0, kn d + cn d'), cn = 2 beta sqrt(m_eff kn).
//
// Reference: T. Schwager and T. Poeschel (2007), "Coefficient of restitution and linear-dashpot
// model revisited", Granular Matter 9, 465-469, doi:10.1007/s10035-007-0065-z.
//
// Derivation. With w0 = sqrt(kn/m_eff), the overlap d obeys, while the force is positive,
//     d'' + 2 beta w0 d' + w0^2 d = 0,   d(0) = 0,  d'(0) = v0 > 0 (approach speed).
// The contact ends when the force kn d + cn d' = -m_eff d'' first returns to zero. That happens
// while d > 0 still: the dashpot would have to pull to keep the particles together until d = 0,
// and this law never pulls. (The textbook e = exp(-pi beta / sqrt(1 - beta^2)) is the velocity
// ratio at d = 0, i.e. it lets the dashpot pull; it overestimates the dissipation.)
//
// Underdamped, beta < 1: with w = w0 sqrt(1 - beta^2) and s = sqrt(1 - beta^2),
//     d(t)  = (v0/w) exp(-beta w0 t) sin(w t)
//     d'(t) = v0 exp(-beta w0 t) [cos(w t) - (beta/s) sin(w t)]
//     d''(t) = -(v0 w0) exp(-beta w0 t) [((1 - 2 beta^2)/s) sin(w t) + 2 beta cos(w t)]
// d'' = 0 at the first theta = w t > 0 with tan(theta) = -2 beta s / (1 - 2 beta^2):
//     theta_c = pi - atan2(2 beta s, 1 - 2 beta^2),   t_c = theta_c / w.
// There sin(theta_c) = 2 beta s and cos(theta_c) = -(1 - 2 beta^2) (the pair has norm 1), so
// the bracket of d' equals -1 and
//     e = -d'(t_c)/v0 = exp(-beta theta_c / s).
// beta = 0 gives t_c = pi/w0, e = 1. As beta -> 1, theta_c -> 2 s, t_c -> 2/w0, e -> exp(-2).
//
// Overdamped, beta > 1: with roots l1,2 = w0 (-beta +- sqrt(beta^2 - 1)), l2 < l1 < 0,
//     d(t) = v0 (exp(l1 t) - exp(l2 t)) / (l1 - l2)
// d'' = 0 where l1^2 exp(l1 t) = l2^2 exp(l2 t):
//     t_c = 2 ln(l2/l1) / (l1 - l2),   e = -d'(t_c)/v0 = (l1/l2) exp(l1 t_c).
// Critical, beta = 1: d = v0 t exp(-w0 t), t_c = 2/w0, e = exp(-2), the common limit.
#pragma once

#include <cmath>
#include <numbers>

namespace mfdem::test {

// Duration of a contact that starts at d = 0 with approach speed v0 (independent of v0), s.
// omega0 = sqrt(kn/m_eff) [rad/s], beta = fraction of critical damping [-].
inline double contact_duration_without_tension(double beta, double omega0) {
  if (beta < 1.0) {
    const double s = std::sqrt(1.0 - beta * beta);
    const double theta = std::numbers::pi - std::atan2(2.0 * beta * s, 1.0 - 2.0 * beta * beta);
    return theta / (omega0 * s);
  }
  if (beta == 1.0) return 2.0 / omega0;
  const double r = std::sqrt(beta * beta - 1.0);
  const double l1 = omega0 * (-beta + r), l2 = omega0 * (-beta - r);
  return 2.0 * std::log(l2 / l1) / (l1 - l2);
}

// Normal coefficient of restitution (rebound over approach normal speed), -.
inline double restitution_without_tension(double beta) {
  if (beta < 1.0) {
    const double s = std::sqrt(1.0 - beta * beta);
    const double theta = std::numbers::pi - std::atan2(2.0 * beta * s, 1.0 - 2.0 * beta * beta);
    return std::exp(-beta * theta / s);
  }
  if (beta == 1.0) return std::exp(-2.0);
  // Scale-free: take omega0 = 1.
  const double r = std::sqrt(beta * beta - 1.0);
  const double l1 = -beta + r, l2 = -beta - r;
  const double t = 2.0 * std::log(l2 / l1) / (l1 - l2);
  return (l1 / l2) * std::exp(l1 * t);
}

// The textbook value that allows the dashpot to pull (contact until d returns to 0), beta < 1.
inline double restitution_with_tension(double beta) {
  return std::exp(-std::numbers::pi * beta / std::sqrt(1.0 - beta * beta));
}

}  // namespace mfdem::test
