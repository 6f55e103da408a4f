// The solver checks plane walls only for the elements near them (Simulation::scan_walls, a
// speed-up); these tests drive walls from far away or move them by hand and require that the
// contact is still met exactly when the geometry says it begins.
#include <catch2/catch.hpp>

#include <cmath>

#include "tests/physics/scene_helpers.hpp"

using namespace mfdem;
using namespace mfdem::test;

namespace {

constexpr double kRadius = 0.01;  // m
constexpr double kDt = 1e-5;      // s

dem::Simulation sliding_sphere(const dem::PlaneWall& wall) {
  const auto material = make_material("grain", 1e7, 1e7, 0.5, 0.0);
  dem::Simulation sim(box_domain(Vec3::Constant(-1.0), Vec3::Constant(1.0)), one_material(material),
                      fixed_step(kDt));
  // Sliding along the wall's plane at 0.03 m/s, which gives the energy guard a scale; the
  // neighbour list is then rebuilt only every 3,300 steps, not in time to meet the wall.
  sim.add_sphere(sphere(Vec3::Zero(), kRadius, 0, Vec3(0.03, 0.0, 0.0)));
  sim.add_wall(wall);
  sim.prepare();
  return sim;
}

}  // namespace

TEST_CASE("a wall driven from far away touches a sphere at the step it arrives",
          "[dem][walls]") {
  // The wall starts 0.10001 m (50 skins) below the sphere's surface and rises at 2 m/s.
  // Reference: the gap at the force evaluation of step k (walls move at the end of a step) is
  // g0 - v (k - 1) dt, so the first touching step is the first k with v (k - 1) dt > g0: k = 5002.
  // g0 lies half a step's travel (1e-5 m) from a step boundary, far beyond the rounding of the
  // wall's summed position (~1e-13 m), so the step must be exact.
  const double g0 = 0.10001, v = 2.0;
  dem::PlaneWall wall = floor_wall(0, -kRadius - g0);
  wall.velocity = Vec3(0.0, 0.0, v);
  dem::Simulation sim = sliding_sphere(wall);
  const int expected = static_cast<int>(std::floor(g0 / (v * kDt))) + 2;  // 5000.5 -> 5002
  int first = -1;
  for (int k = 1; k <= expected + 10 && first < 0; ++k) {
    sim.step();
    if (sim.bodies().velocity[0].z() != 0.0) first = k;
  }
  CAPTURE(expected, first);
  CHECK(first == expected);
}

TEST_CASE("a wall moved by hand onto a sphere acts at the next step", "[dem][walls]") {
  // The wall starts 0.5 m away and is set, between two steps, 1 mm into the sphere. Reference:
  // the next step's wall force is the spring's, kn x 1 mm (kn = series(1e7, 1e7) = 5e6 N/m,
  // no damping) = 5000 N. Tolerance: the sphere moves during the step, by v dt with
  // v = F dt / (2 m) ~ 3e-3 m/s: 3e-8 m of 1e-3 m, so 1e-4 relative.
  dem::Simulation sim = sliding_sphere(floor_wall(0, -0.5));
  for (int k = 0; k < 10; ++k) sim.step();
  CHECK(sim.wall_force(0).norm() == 0.0);
  sim.mutable_walls()[0].point = Vec3(0.0, 0.0, -kRadius + 1e-3);
  sim.step();
  CHECK(floor_normal_force(sim) == Approx(5000.0).epsilon(1e-4));
}
