// Closed-form mass properties of spheres whose centres lie on the x axis, each overlapping only
// its neighbours: the reference for the clump integration.
//
// The union of balls splits exactly along the radical planes of neighbouring pairs (on ball i's
// side of the plane, every point of ball i+1 also lies in ball i), so
//   union = sum over balls of (ball minus the caps cut off by its radical planes).
// Radical plane of balls (x_i, R_i), (x_j, R_j), d = x_j - x_i: at a = (d^2 + R_i^2 - R_j^2) / (2d)
// from x_i. For equal radii it is the mid-plane and the lens cut out of the two balls has the
// volume V_lens = pi (4R + d)(2R - d)^2 / 12.
// A cap {u > t} of a ball of radius R (u along the cap's axis from the centre, h = R - t), with
// disk area pi (R^2 - u^2) at height u, has the exact moments
//   V    = pi h^2 (3R - h) / 3
//   S_u  = integral of u      = pi [R^2 u^2/2 - u^4/4]            from t to R
//   S_uu = integral of u^2    = pi [R^2 u^3/3 - u^5/5]            from t to R
//   S_vv = integral of v^2    = pi/4 [R^4 u - 2 R^2 u^3/3 + u^5/5] from t to R  (v across the axis)
// Touching balls (d = R_i + R_j) have empty caps: the union is the sum of the balls, combined by
// the parallel axis theorem.
#pragma once

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "fidelity/mass_properties.hpp"

namespace mfdem::test {

struct RowSphere {
  double x;
  double radius;
};

// Moments of the cap of a ball at the origin beyond the plane u = t along +x (side = +1) or -x
// (side = -1).
inline fidelity::Moments cap_moments(double radius, double t, int side) {
  using std::numbers::pi;
  const double R = radius;
  auto su = [&](double u) { return pi * (R * R * u * u / 2 - u * u * u * u / 4); };
  auto suu = [&](double u) { return pi * (R * R * u * u * u / 3 - std::pow(u, 5) / 5); };
  auto svv = [&](double u) { return pi / 4 * (std::pow(R, 4) * u - 2 * R * R * u * u * u / 3 + std::pow(u, 5) / 5); };
  const double h = R - t;
  fidelity::Moments cap;
  cap.volume = pi * h * h * (3 * R - h) / 3;
  cap.first = fidelity::Vec3(side * (su(R) - su(t)), 0, 0);
  cap.second.diagonal() << suu(R) - suu(t), svv(R) - svv(t), svv(R) - svv(t);
  return cap;
}

inline fidelity::MassProperties sphere_row_exact(const std::vector<RowSphere>& row) {
  fidelity::Moments total;
  for (std::size_t i = 0; i < row.size(); ++i) {
    fidelity::Moments ball = fidelity::ball_moments(fidelity::Vec3::Zero(), row[i].radius);
    if (i + 1 < row.size()) {  // cap towards the next ball
      const double d = row[i + 1].x - row[i].x;
      if (d < row[i].radius + row[i + 1].radius) {
        const double a = (d * d + row[i].radius * row[i].radius - row[i + 1].radius * row[i + 1].radius) / (2 * d);
        ball -= cap_moments(row[i].radius, a, +1);
      }
    }
    if (i > 0) {  // cap towards the previous ball
      const double d = row[i].x - row[i - 1].x;
      if (d < row[i].radius + row[i - 1].radius) {
        const double a = (d * d + row[i].radius * row[i].radius - row[i - 1].radius * row[i - 1].radius) / (2 * d);
        ball -= cap_moments(row[i].radius, a, -1);
      }
    }
    total += ball.translated(fidelity::Vec3(row[i].x, 0, 0));
  }
  for (std::size_t i = 0; i + 2 < row.size(); ++i)
    if (row[i + 2].x - row[i].x < row[i].radius + row[i + 2].radius)
      throw std::invalid_argument("sphere_row_exact: only neighbours may overlap");
  return fidelity::mass_properties(total);
}

}  // namespace mfdem::test
