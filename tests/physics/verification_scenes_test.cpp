// The example scenes of studies/scenes/verification/ load, run to their duration, and give the
// numbers their comments promise, so that neither the files nor their comments rot.
// Each check repeats, with the tolerance stated there, a closed form of the matching test in
// tests/physics/ (where the derivations are).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include "studies/scene/scene_file.hpp"
#include "tests/physics/linear_dashpot.hpp"
#include "tests/physics/scene_helpers.hpp"

using namespace mfdem;
using namespace mfdem::test;

namespace {

std::filesystem::path verification_scene(const std::string& name) {
  return std::filesystem::path(MFDEM_SOURCE_DIR) / "studies" / "scenes" / "verification" / name;
}

// Loads the scene, runs it for its duration as `mfdem run` does, and returns the solver.
dem::Simulation run_scene(const scene::Scene& s) {
  dem::Simulation sim = scene::make_simulation(s);
  sim.prepare();
  const std::int64_t steps = std::llround(s.duration / sim.time_step());
  for (std::int64_t k = 0; k < steps; ++k) sim.step();
  return sim;
}

double kinetic_energy(const scene::Scene& s) {
  double e = 0.0;
  for (const auto& sphere : s.spheres)
    e += 0.5 * sphere_mass(sphere.radius) * sphere.velocity.squaredNorm();
  return e;
}

}  // namespace

TEST_CASE("the verification example scenes load, run and give their documented results",
          "[physics][scenes]") {
  const SerialThreads serial;

  SECTION("normal_impact.toml: restitution 0.451 without tension, momentum kept") {
    const scene::Scene s = scene::load_scene(verification_scene("normal_impact.toml"));
    REQUIRE(s.spheres.size() == 3);
    REQUIRE(s.walls.size() == 1);
    const dem::Simulation sim = run_scene(s);
    const double beta = 0.3, e_ref = restitution_without_tension(beta);  // 0.4510
    const auto& v = sim.bodies().velocity;
    const double w0_dt = std::sqrt(dem::series_stiffness(2e7, 5e7) /
                                   (sphere_mass(0.02) * sphere_mass(0.03) /
                                    (sphere_mass(0.02) + sphere_mass(0.03)))) * sim.time_step();
    const double tolerance = beta * w0_dt + 2.0 * w0_dt * w0_dt;  // as in normal_impact_test.cpp
    CHECK(std::abs(v[0].z() / 1.0 - e_ref) <= tolerance);
    CHECK(std::abs((v[2].x() - v[1].x()) / 2.0 - e_ref) <= tolerance);
    const double m1 = sphere_mass(0.02), m2 = sphere_mass(0.03);
    CHECK(m1 * v[1].x() + m2 * v[2].x() == Approx(m1 * 1.5 - m2 * 0.5).epsilon(1e-12));
  }

  SECTION("oblique_impact.toml: sliding and sticking rebounds") {
    const scene::Scene s = scene::load_scene(verification_scene("oblique_impact.toml"));
    REQUIRE(s.spheres.size() == 2);
    const dem::Simulation sim = run_scene(s);
    const double radius = 0.02, w_dt = std::sqrt(1.5e7 / sphere_mass(radius)) * sim.time_step();
    const auto& v = sim.bodies().velocity;
    const auto& w = sim.bodies().angular_velocity;
    // Sliding, mu = 0.3: vx' = 5 - 0.6 = 4.4 m/s (exact while capped), R wy' = 1.5 m/s within
    // the lever d_max/(2R) < 0.2 %.
    CHECK(v[0].x() == Approx(4.4).epsilon(1e-4));
    CHECK(radius * w[0].y() == Approx(1.5).epsilon(2e-3));
    // Sticking: vx' = 3/7 vt, R wy' = 10/7 vt, within w dt vt.
    CHECK(std::abs(v[1].x() - 3.0 / 7.0) <= w_dt);
    CHECK(std::abs(radius * w[1].y() - 10.0 / 7.0) <= w_dt);
    CHECK(sim.energy().total() == Approx(kinetic_energy(s)).epsilon(1e-3));
  }

  SECTION("column.toml: each contact carries the weight above it") {
    const scene::Scene s = scene::load_scene(verification_scene("column.toml"));
    REQUIRE(s.spheres.size() == 6);
    const dem::Simulation sim = run_scene(s);
    const double weight = sphere_mass(0.02) * 9.81;
    const auto contacts = sim.contacts();
    REQUIRE(contacts.size() == 5);
    for (const auto& c : contacts)
      CHECK(c.force.z() == Approx((6 - c.body_b) * weight).epsilon(1e-6));
    CHECK(-sim.wall_force(0).z() == Approx(6.0 * weight).epsilon(1e-6));
    CHECK(sim.energy().kinetic() < 1e-20);
  }

  SECTION("energy_box.toml: 30 elastic spheres keep their energy") {
    const scene::Scene s = scene::load_scene(verification_scene("energy_box.toml"));
    REQUIRE(s.spheres.size() == 30);
    REQUIRE(s.walls.size() == 6);
    const dem::Simulation sim = run_scene(s);
    // Bound (w dt)^2/4 of the initial kinetic energy with w = sqrt(7 ks/m) (energy_balance_test).
    const double w_dt = std::sqrt(7.0 * 1e7 / sphere_mass(0.02)) * sim.time_step();
    const double e0 = kinetic_energy(s);
    CHECK(std::abs(sim.energy().total() - e0) <= w_dt * w_dt / 4.0 * e0);
    CHECK(sim.energy().dissipated() == 0.0);
  }
}
