// Clumps in contact: coming to rest on a floor, and static/sliding friction on an incline.
#include <catch2/catch.hpp>

#include <cmath>

#include "dem/simulation.hpp"
#include "tests/clumps/clump_builders.hpp"

using namespace mfdem;
using dem::Vec3;

namespace {

dem::Simulation floor_scene(const dem::MaterialTable& materials, const Vec3& gravity) {
  dem::Domain domain;
  domain.min = Vec3(-1.0, -1.0, 0.0);
  domain.max = Vec3(1.0, 1.0, 1.0);
  dem::SimulationSettings settings;
  settings.gravity = gravity;
  dem::Simulation sim(domain, materials, settings);
  dem::PlaneWall floor;
  floor.name = "floor";
  sim.add_wall(floor);
  return sim;
}

}  // namespace

TEST_CASE("a clump dropped on a floor comes to rest and never gains energy", "[clump][contact]") {
  // Reference: with damping and friction and no work put in, kinetic + potential + elastic
  // energy can only fall. Tolerance: the velocity-Verlet energy error of a contact oscillates
  // with amplitude ~ (w dt)^2 of the contact energy; we allow 1e-3 of the drop height's
  // potential energy between checks. At rest after 1.5 s: kinetic energy below 1e-5 of the drop
  // energy (the tangential springs carry a small undamped torsional rocking: the law has no
  // tangential dashpot, as in PFC).
  // A flat clump: a row of pebbles would roll on forever, rightly, as it has no rolling
  // resistance.
  auto clump = test::flat_triangle(0.02, 2800.0);
  clump.position = Vec3(0.0, 0.0, 0.2);
  clump.orientation = dem::Quat(Eigen::AngleAxisd(0.4, Vec3(1.0, 2.0, 0.5).normalized()));
  clump.velocity = Vec3(0.2, 0.0, 0.0);
  clump.angular_velocity = Vec3(3.0, -2.0, 5.0);
  dem::Simulation sim = floor_scene(test::one_material(1e5, 0.5, 0.3), Vec3(0.0, 0.0, -9.81));
  sim.add_clump(clump);
  sim.prepare();
  auto mechanical = [&] {
    const auto e = sim.energy();
    return e.kinetic() + e.gravitational + e.elastic;
  };
  const double drop_energy = clump.mass * 9.81 * 0.2;
  double previous = mechanical();
  double worst_rise = 0.0;
  const int steps = static_cast<int>(1.5 / sim.time_step());
  for (int k = 0; k < steps; ++k) {
    sim.step();
    if (k % 50 == 0) {
      const double now = mechanical();
      worst_rise = std::max(worst_rise, now - previous);
      previous = now;
    }
  }
  CAPTURE(worst_rise, drop_energy, sim.bodies().velocity[0].norm());
  CHECK(worst_rise < 1e-3 * drop_energy);
  CHECK(sim.energy().kinetic() < 1e-5 * drop_energy);
  // At rest the floor carries the weight: reference m g, tolerance 1e-3 relative.
  CHECK(sim.wall_force(0).z() == Approx(-clump.mass * 9.81).epsilon(1e-3));
}

TEST_CASE("a flat three-pebble clump on an incline sticks below tan(theta) = mu and slides above",
          "[clump][contact][friction]") {
  // Reference: a rigid block on a plane with Coulomb friction: at rest for tan(theta) < mu,
  // otherwise a = g (sin(theta) - mu cos(theta)) down the slope. The incline is made by tilting
  // gravity. Tolerances: static case, creep below 1 mm over 0.5 s (the elastic tangential
  // springs settle by ~ m g sin / ks ~ 1e-6 m); sliding case, acceleration within 2 % (contact
  // oscillations at start, measured between 0.2 s and 0.5 s).
  const double mu = 0.5;
  for (double theta_deg : {20.0, 35.0}) {
    const double theta = theta_deg * test::kPi / 180.0;
    const double g = 9.81;
    const Vec3 gravity(g * std::sin(theta), 0.0, -g * std::cos(theta));
    auto clump = test::flat_triangle(0.02, 2800.0);
    clump.position = Vec3(0.0, 0.0, 0.02);  // pebbles just touching the floor
    dem::Simulation sim = floor_scene(test::one_material(1e5, mu, 0.7, 0.0), gravity);
    sim.add_clump(clump);
    sim.prepare();
    auto run_until = [&](double t) {
      while (sim.time() < t) sim.step();
    };
    run_until(0.2);
    const double x1 = sim.bodies().position[0].x();
    const double v1 = sim.bodies().velocity[0].x();
    run_until(0.5);
    const double x2 = sim.bodies().position[0].x();
    const double v2 = sim.bodies().velocity[0].x();
    CAPTURE(theta_deg, x1, x2, v1, v2);
    if (std::tan(theta) < mu) {
      CHECK(std::abs(x2 - x1) < 1e-3);
    } else {
      const double expected = g * (std::sin(theta) - mu * std::cos(theta));
      CHECK((v2 - v1) / 0.3 == Approx(expected).epsilon(0.02));
    }
  }
}
