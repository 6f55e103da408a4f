// Small scenes for the solver verification tests in tests/dem/, built through the public
// dem::Simulation API. Everything a test depends on is set explicitly here (no hidden defaults),
// so that a reference value in a test can be derived from the numbers it passes in.
// Namespace mfdem::dem_test keeps these apart from the helpers of other test folders (one
// executable links them all).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "tests/support/sphere_spec.hpp"
#include "dem/simulation.hpp"

namespace mfdem::dem_test {

using dem::Vec3;

// Ballast density (the paper's Table 1), kg/m^3, and standard gravity, m/s^2.
inline constexpr double kDensity = 2800.0;
inline constexpr double kGravity = 9.81;

// m = rho (4/3) pi R^3, kg.
inline double sphere_mass(double radius, double density = kDensity) {
  return density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

// I = (2/5) m R^2 of a solid sphere, kg m^2.
inline double sphere_inertia(double radius, double density = kDensity) {
  return 0.4 * sphere_mass(radius, density) * radius * radius;
}

// Every channel of a material, named. Stiffnesses are per material, in N/m; the contact spring
// of two equal materials is half of it (series mixing, dem/material.hpp).
struct MaterialParameters {
  std::string name = "ballast";
  double stiffness = 2e7;       // kn = ks, N/m
  double friction = 0.5;        // mu
  double rolling_friction = 0;  // mu_r
  double damping_ratio = 0;     // beta_n
  double local_damping = 0;     // alpha
  double density = kDensity;    // kg/m^3
};

inline dem::Material make_material(const MaterialParameters& p) {
  dem::Material m;
  m.name = p.name;
  m.density = p.density;
  m.normal_stiffness = p.stiffness;
  m.shear_stiffness = p.stiffness;
  m.friction = p.friction;
  m.rolling_friction = p.rolling_friction;
  m.damping_ratio = p.damping_ratio;
  m.local_damping = p.local_damping;
  return m;
}

inline dem::MaterialTable material_table(const std::vector<MaterialParameters>& list) {
  dem::MaterialTable table;
  for (const auto& p : list) table.add(make_material(p));
  return table;
}

inline dem::Domain box_domain(const Vec3& min, const Vec3& max,
                              std::array<bool, 3> periodic = {false, false, false}) {
  dem::Domain d;
  d.min = min;
  d.max = max;
  d.periodic = periodic;
  return d;
}

inline dem::SimulationSettings settings(const Vec3& gravity, double time_step = 0.0) {
  dem::SimulationSettings s;
  s.gravity = gravity;
  s.time_step = time_step;
  return s;
}

// The plane z = 0 with normal +z.
inline dem::PlaneWall floor_wall(int material) {
  dem::PlaneWall w;
  w.name = "floor";
  w.point = Vec3::Zero();
  w.normal = Vec3::UnitZ();
  w.material = material;
  return w;
}

using test_support::sphere;

// Spheres on a simple cubic lattice of `n` cells per axis starting at `origin` with spacing
// `pitch`, radii uniform in [r_min, r_max] and velocities uniform in a cube of half-width
// `speed`, from a fixed seed (std::mt19937_64 is fully specified by the standard; the
// conversion to double is done here by hand so that the scene is the same with every library).
inline std::vector<dem::SphereSpec> lattice(const std::array<int, 3>& n, const Vec3& origin,
                                            double pitch, double r_min, double r_max,
                                            double speed, std::uint64_t seed, int material = 0,
                                            long long limit = -1) {
  std::mt19937_64 rng(seed);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  std::vector<dem::SphereSpec> out;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        if (limit >= 0 && static_cast<long long>(out.size()) >= limit) return out;
        const double r = r_min + (r_max - r_min) * uniform();
        const Vec3 v(speed * (2 * uniform() - 1), speed * (2 * uniform() - 1),
                     speed * (2 * uniform() - 1));
        out.push_back(sphere(origin + pitch * Vec3(i + 0.5, j + 0.5, k + 0.5), r, material, v));
      }
  return out;
}

inline bool all_finite(const std::vector<Vec3>& values) {
  for (const auto& v : values)
    if (!v.allFinite()) return false;
  return true;
}

}  // namespace mfdem::dem_test
