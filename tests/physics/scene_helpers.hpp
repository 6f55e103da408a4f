// Small builders for the physics verification tests: materials, a floor, a pair of spheres,
// and the closed-form mass of a sphere. Everything goes through the public dem::Simulation API.
#pragma once

#include <omp.h>

#include <cmath>
#include <numbers>
#include <string>

#include "tests/support/sphere_spec.hpp"
#include "dem/simulation.hpp"

namespace mfdem::test {

using dem::Vec3;

// Runs the enclosing scope on one OpenMP thread and restores the previous count after. The
// solver gives bitwise the same trajectory for any thread count (tests/dem checks that), so
// physics results do not change; but these scenes have 1-30 bodies, far below the work that
// pays for a fork-join, and under `ctest -j2` two test processes of two threads each share two
// cores, where spin-waiting threads made a 20,000-step run of 30 spheres take 18 s instead of
// 0.15 s.
class SerialThreads {
 public:
  SerialThreads() : previous_(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~SerialThreads() { omp_set_num_threads(previous_); }
  SerialThreads(const SerialThreads&) = delete;
  SerialThreads& operator=(const SerialThreads&) = delete;

 private:
  int previous_;
};

// Density of ballast stone (the paper's Table 1), kg/m^3.
constexpr double kDensity = 2800.0;

// m = rho (4/3) pi R^3, kg.
inline double sphere_mass(double radius, double density = kDensity) {
  return density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

// I = (2/5) m R^2 of a solid sphere, kg m^2.
inline double sphere_inertia(double radius, double density = kDensity) {
  return 0.4 * sphere_mass(radius, density) * radius * radius;
}

// One material; kn, ks in N/m (mixed in series per contact), mu, beta and alpha dimensionless.
inline dem::Material make_material(const std::string& name, double kn, double ks, double friction,
                                   double damping_ratio, double local_damping = 0.0) {
  dem::Material m;
  m.name = name;
  m.density = kDensity;
  m.normal_stiffness = kn;
  m.shear_stiffness = ks;
  m.friction = friction;
  m.damping_ratio = damping_ratio;
  m.local_damping = local_damping;
  return m;
}

inline dem::MaterialTable one_material(const dem::Material& m) {
  dem::MaterialTable table;
  table.add(m);
  return table;
}

inline dem::MaterialTable two_materials(const dem::Material& a, const dem::Material& b) {
  dem::MaterialTable table;
  table.add(a);
  table.add(b);
  return table;
}

// A fixed step and no gravity unless asked: the verification cases control both.
inline dem::SimulationSettings fixed_step(double dt, const Vec3& gravity = Vec3::Zero()) {
  dem::SimulationSettings s;
  s.time_step = dt;
  s.gravity = gravity;
  return s;
}

inline dem::Domain box_domain(const Vec3& min, const Vec3& max) {
  dem::Domain d;
  d.min = min;
  d.max = max;
  return d;
}

// The plane z = height, normal +z: a floor under the spheres.
inline dem::PlaneWall floor_wall(int material, double height = 0.0) {
  dem::PlaneWall w;
  w.name = "floor";
  w.point = Vec3(0.0, 0.0, height);
  w.normal = Vec3::UnitZ();
  w.material = material;
  return w;
}

using test_support::sphere;

// Two spheres on the x axis approaching head-on: a (radius ra, material 0) at the origin moving
// at +va, b (radius rb, material of index material_b) `gap` beyond contact moving at -vb.
inline dem::Simulation sphere_pair(const dem::MaterialTable& materials, double ra, double rb,
                                   int material_b, double va, double vb, double gap, double dt) {
  const double reach = 2.0 * (ra + rb) + gap;
  dem::Simulation sim(box_domain(Vec3(-reach, -reach, -reach), Vec3(2.0 * reach, reach, reach)),
                      materials, fixed_step(dt));
  sim.add_sphere(sphere(Vec3::Zero(), ra, 0, Vec3(va, 0.0, 0.0)));
  sim.add_sphere(sphere(Vec3(ra + rb + gap, 0.0, 0.0), rb, material_b, Vec3(-vb, 0.0, 0.0)));
  return sim;
}

// Normal force magnitude on the floor wall w during the last step (the wall pushes up), N.
inline double floor_normal_force(const dem::Simulation& sim, int w = 0) {
  return -sim.wall_force(w).dot(sim.walls()[w].normal);
}

}  // namespace mfdem::test
