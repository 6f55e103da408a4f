// The mean unbalanced force ratio, PFC's equilibrium measure (the settling criterion of bed
// preparation): mean over bodies of |net force| / mean over contacts of |contact force|.
//
// References: (a) two spheres pressed together in zero gravity: each body's net force is the
// contact force, so the ratio is exactly 1 (tolerance 1e-12, round-off of two norms);
// (b) a settled column on a floor: net forces vanish, so the ratio falls below 1e-6 (the
// column test settles to 1e-8 m g per body; the mean contact force is ~3.5 m g);
// (c) before any two bodies touch the ratio is infinite (no contact force to compare with).
#include <catch2/catch.hpp>

#include <cmath>

#include "tests/physics/scene_helpers.hpp"

using namespace mfdem;
using namespace mfdem::test;

TEST_CASE("the unbalanced force ratio is 1 for an isolated pressed pair and 0 at rest",
          "[physics][statics]") {
  const SerialThreads serial;
  const double radius = 0.02;
  SECTION("two spheres pressed together, no gravity") {
    const auto materials = one_material(make_material("stone", 2e7, 2e7, 0.5, 0.0));
    auto sim = sphere_pair(materials, radius, radius, 0, 0.0, 0.0, -1e-4, 1e-6);
    sim.prepare();
    sim.step();
    REQUIRE(std::abs(sim.unbalanced_force_ratio() - 1.0) < 1e-12);
  }
  SECTION("a column at rest on a floor") {
    const auto materials = two_materials(make_material("stone", 2e7, 2e7, 0.5, 0.5, 0.7),
                                         make_material("floor", 5e7, 5e7, 0.5, 0.5));
    dem::SimulationSettings settings;
    dem::Simulation sim(box_domain(Vec3(-0.1, -0.1, -0.05), Vec3(0.1, 0.1, 0.5)), materials, settings);
    for (int k = 0; k < 4; ++k) sim.add_sphere(sphere(Vec3(0.0, 0.0, radius * (1 + 2 * k) + 1e-4 * k), radius, 0));
    sim.add_wall(floor_wall(1));
    sim.prepare();
    sim.step();
    REQUIRE(std::isinf(sim.unbalanced_force_ratio()));  // the spheres start apart
    for (int k = 0; k < 200000 && !(sim.unbalanced_force_ratio() < 1e-6); ++k) sim.step();
    INFO("ratio " << sim.unbalanced_force_ratio() << " after " << sim.time() << " s");
    REQUIRE(sim.unbalanced_force_ratio() < 1e-6);
  }
}
