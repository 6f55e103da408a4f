#pragma once
// Small clumps with closed-form mass properties for the solver's rigid-body tests.
#include <cmath>

#include "dem/simulation.hpp"

namespace mfdem::test {

inline constexpr double kPi = 3.14159265358979323846;

// Three equal, touching (non-overlapping) pebbles in a row along x: the mass properties are the
// sum of the spheres' with the parallel-axis theorem, exactly.
inline dem::ClumpSpec three_in_a_row(double radius, double density) {
  const double m1 = density * 4.0 / 3.0 * kPi * radius * radius * radius;
  const double i1 = 0.4 * m1 * radius * radius;
  dem::ClumpSpec c;
  c.mass = 3.0 * m1;
  const double d = 2.0 * radius;
  c.principal_inertia = dem::Vec3(3.0 * i1, 3.0 * i1 + 2.0 * m1 * d * d, 3.0 * i1 + 2.0 * m1 * d * d);
  c.pebbles = {{dem::Vec3(-d, 0, 0), radius}, {dem::Vec3::Zero(), radius}, {dem::Vec3(d, 0, 0), radius}};
  return c;
}

// Three equal touching pebbles at the corners of an equilateral triangle in the body x-y plane
// (a flat clump that rests on three points).
inline dem::ClumpSpec flat_triangle(double radius, double density) {
  const double m1 = density * 4.0 / 3.0 * kPi * radius * radius * radius;
  const double i1 = 0.4 * m1 * radius * radius;
  const double rc = 2.0 * radius / std::sqrt(3.0);  // circumradius of the triangle of centres
  dem::ClumpSpec c;
  c.mass = 3.0 * m1;
  // In-plane axes: 3 i1 + m1 * sum of squared distances to the axis = 3 i1 + 1.5 m1 rc^2;
  // normal axis: 3 i1 + 3 m1 rc^2.
  c.principal_inertia = dem::Vec3(3.0 * i1 + 1.5 * m1 * rc * rc, 3.0 * i1 + 1.5 * m1 * rc * rc,
                                  3.0 * i1 + 3.0 * m1 * rc * rc);
  for (int k = 0; k < 3; ++k) {
    const double a = 2.0 * kPi * k / 3.0;
    c.pebbles.push_back({dem::Vec3(rc * std::cos(a), rc * std::sin(a), 0.0), radius});
  }
  return c;
}

inline dem::MaterialTable one_material(double kn, double mu, double beta, double alpha = 0.0) {
  dem::MaterialTable t;
  dem::Material m;
  m.name = "stone";
  m.density = 2800.0;
  m.normal_stiffness = kn;
  m.shear_stiffness = kn;
  m.friction = mu;
  m.damping_ratio = beta;
  m.local_damping = alpha;
  t.add(m);
  return t;
}

}  // namespace mfdem::test
