// A column of N equal spheres resting on a floor under gravity.
//
// Reference (statics): the k-th contact from the top carries the weight of the k spheres above
// it, Fk = k m g, and the floor carries N m g; with the linear spring each contact is compressed
// by dk = Fk / kn, kn = series(kn_stone, kn_stone) between spheres and
// series(kn_stone, kn_floor) on the floor.
// Tolerance 1e-6 relative: Newton's law for the spheres above contact k gives
// |Fk - k m g| <= sum of their net forces, and the run goes on until every sphere's net force
// is below 1e-8 m g (and its speed below 1e-9 m/s), so k x 1e-8 <= 6e-8 of the weight at most;
// 1e-6 leaves room for round-off in the contact sums (overlaps ~1e-5 m against centres ~0.1 m
// lose about 1e-11 relative).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "tests/physics/scene_helpers.hpp"

using namespace mfdem;
using namespace mfdem::test;

TEST_CASE("a settled column of spheres carries the weight above each contact",
          "[physics][statics]") {
  const SerialThreads serial;
  constexpr int kCount = 6;
  const double radius = 0.02, g = 9.81;
  const double kn_stone = 2e7, kn_floor = 5e7;
  // Viscous (beta = 0.5) and local (alpha = 0.5) damping only to settle; statics do not see them.
  const auto materials = two_materials(make_material("stone", kn_stone, kn_stone, 0.5, 0.5, 0.5),
                                       make_material("floor", kn_floor, kn_floor, 0.5, 0.5));
  dem::SimulationSettings settings;  // automatic step, 0.2 of the critical one
  settings.gravity = Vec3(0.0, 0.0, -g);
  dem::Simulation sim(box_domain(Vec3(-0.1, -0.1, -0.05), Vec3(0.1, 0.1, 2.0 * radius * kCount + 0.05)),
                      materials, settings);
  for (int k = 0; k < kCount; ++k)
    sim.add_sphere(sphere(Vec3(0.0, 0.0, radius + 2.0 * radius * k), radius, 0));
  sim.add_wall(floor_wall(1));
  sim.prepare();

  const double m = sphere_mass(radius), weight = m * g;
  const auto residual = [&] {
    double worst_force = 0.0, worst_speed = 0.0;
    for (dem::Index b = 0; b < sim.bodies().size(); ++b) {
      worst_force = std::max(worst_force, sim.bodies().force[b].norm());
      worst_speed = std::max(worst_speed, sim.bodies().velocity[b].norm());
    }
    return std::pair{worst_force, worst_speed};
  };
  int steps = 0;
  while (steps < 400000) {
    for (int k = 0; k < 1000; ++k) sim.step();
    steps += 1000;
    const auto [force, speed] = residual();
    if (force < 1e-8 * weight && speed < 1e-9) break;
  }
  const auto [force, speed] = residual();
  INFO("settled after " << steps << " steps (" << sim.time() << " s): net force " << force / weight
                        << " m g, speed " << speed << " m/s");
  REQUIRE(force < 1e-8 * weight);
  REQUIRE(speed < 1e-9);

  const auto contacts = sim.contacts();
  REQUIRE(contacts.size() == kCount - 1);
  const double kn_pair = dem::series_stiffness(kn_stone, kn_stone);
  double worst_force_error = 0.0, worst_overlap_error = 0.0;
  for (const auto& c : contacts) {
    // Bodies are numbered from the floor up; the pair force is on the upper body b.
    REQUIRE(c.body_b == c.body_a + 1);
    const int above = kCount - c.body_b;  // spheres resting on this contact
    const double expected = above * weight;
    worst_force_error = std::max(worst_force_error, (c.force - Vec3(0, 0, expected)).norm() / expected);
    worst_overlap_error = std::max(worst_overlap_error, std::abs(c.overlap - expected / kn_pair) /
                                                            (expected / kn_pair));
  }
  const double floor_load = kCount * weight;
  const double floor_error = (sim.wall_force(0) - Vec3(0, 0, -floor_load)).norm() / floor_load;
  const double floor_overlap = radius - sim.bodies().position[0].z();
  const double kn_wall = dem::series_stiffness(kn_stone, kn_floor);
  const double floor_overlap_error = std::abs(floor_overlap - floor_load / kn_wall) / (floor_load / kn_wall);
  INFO("relative errors: contact forces " << worst_force_error << ", overlaps " << worst_overlap_error
                                          << ", floor force " << floor_error << ", floor overlap "
                                          << floor_overlap_error);
  CHECK(worst_force_error <= 1e-6);
  CHECK(worst_overlap_error <= 1e-6);
  CHECK(floor_error <= 1e-6);
  CHECK(floor_overlap_error <= 1e-6);
}
