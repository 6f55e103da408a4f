// Rigid clump rotation: torque-free motion, stability of the principal axes, and a one-pebble
// clump against a sphere.
#include <catch2/catch.hpp>

#include "dem/rigid_rotation.hpp"
#include "dem/simulation.hpp"
#include "tests/clumps/clump_builders.hpp"

using namespace mfdem;
using dem::Vec3;

namespace {

dem::Simulation free_space(const dem::ClumpSpec& clump, double dt) {
  dem::Domain domain;
  domain.min = Vec3::Constant(-1.0);
  domain.max = Vec3::Constant(1.0);
  dem::SimulationSettings settings;
  settings.gravity = Vec3::Zero();
  settings.time_step = dt;
  settings.force_time_step = true;  // a lone body never touches anything: no contact limit
  dem::Simulation sim(domain, test::one_material(1e7, 0.5, 0.0), settings);
  sim.add_clump(clump);
  return sim;
}

Vec3 world_angular_momentum(const dem::Simulation& sim) {
  const auto& b = sim.bodies();
  const Vec3 l_body = dem::body_angular_momentum(b.orientation[0], b.inertia[0], b.angular_velocity[0]);
  return b.orientation[0] * l_body;
}

}  // namespace

TEST_CASE("a torque-free asymmetric clump keeps its angular momentum and kinetic energy",
          "[clump][rotation]") {
  // Reference: Euler's equations without torque conserve L (world) and the rotational energy.
  // The splitting scheme conserves L exactly up to round-off (~1e-16 per step, 1e5 steps) and
  // the energy to a bounded O((w dt)^2) oscillation: here w dt ~ 2e-3, so 1e-5 is a safe bound.
  // Measured on this scheme: 1.0e-10 for L (round-off of the L <-> w conversions), 7.5e-8 for E.
  auto clump = test::three_in_a_row(0.02, 2800.0);
  clump.angular_velocity = Vec3(3.0, 1.0, 2.0);
  dem::Simulation sim = free_space(clump, 5e-4);
  sim.prepare();
  const Vec3 l0 = world_angular_momentum(sim);
  const double e0 = sim.energy().kinetic_rotational;
  double worst_l = 0.0, worst_e = 0.0;
  for (int k = 0; k < 100000; ++k) {
    sim.step();
    if (k % 1000 == 999) {
      worst_l = std::max(worst_l, (world_angular_momentum(sim) - l0).norm() / l0.norm());
      worst_e = std::max(worst_e, std::abs(sim.energy().kinetic_rotational - e0) / e0);
    }
  }
  CAPTURE(worst_l, worst_e);
  CHECK(worst_l < 1e-9);
  CHECK(worst_e < 1e-5);
}

TEST_CASE("rotation about the intermediate principal axis is unstable, about the others stable",
          "[clump][rotation]") {
  // Reference: the tennis-racket theorem (Euler's equations linearised about steady spin): a
  // perturbation of 1e-4 rad/s grows exponentially about the intermediate axis and stays of its
  // own size about the largest and smallest axes. Tolerance: "stays" = below 100x its start
  // within 4 s; "grows" = reaches the size of the spin (above 10 % of it).
  dem::ClumpSpec clump;
  clump.mass = 1.0;
  clump.principal_inertia = Vec3(1.0, 2.0, 3.0);
  clump.pebbles = {{Vec3(-0.05, 0, 0), 0.02}, {Vec3(0.05, 0, 0), 0.02}};
  for (int axis = 0; axis < 3; ++axis) {
    dem::ClumpSpec c = clump;
    c.angular_velocity = Vec3::Constant(1e-4);
    c.angular_velocity[axis] = 5.0;
    dem::Simulation sim = free_space(c, 5e-4);
    sim.prepare();
    double largest_off_axis = 0.0;
    for (int k = 0; k < 8000; ++k) {
      sim.step();
      const Vec3 w_body = sim.bodies().orientation[0].conjugate() * sim.bodies().angular_velocity[0];
      Vec3 off = w_body;
      off[axis] = 0.0;
      largest_off_axis = std::max(largest_off_axis, off.norm());
    }
    CAPTURE(axis, largest_off_axis);
    if (axis == 1)
      CHECK(largest_off_axis > 0.5);
    else
      CHECK(largest_off_axis < 1e-2);
  }
}

TEST_CASE("a one-pebble clump moves bitwise like the equivalent sphere", "[clump][sphere]") {
  // Run the same drop onto a floor two ways; every state must be identical, not close.
  auto build = [](bool as_clump) {
    dem::Domain domain;
    domain.min = Vec3(-0.5, -0.5, 0.0);
    domain.max = Vec3(0.5, 0.5, 1.0);
    dem::SimulationSettings settings;
    settings.time_step = 2e-5;
    dem::Simulation sim(domain, test::one_material(1e6, 0.5, 0.2), settings);
    dem::PlaneWall floor;
    floor.name = "floor";
    sim.add_wall(floor);
    const double r = 0.02;
    for (int k = 0; k < 3; ++k) {
      const Vec3 x(0.05 * k, 0.01 * k, 0.03 + 0.045 * k);
      const Vec3 v(0.3, -0.1 * k, -0.5);
      if (as_clump) {
        dem::ClumpSpec c;
        c.position = x;
        c.velocity = v;
        c.angular_velocity = Vec3(0.0, 2.0, 1.0);
        c.mass = 2800.0 * 4.0 / 3.0 * test::kPi * r * r * r;
        c.principal_inertia = Vec3::Constant(0.4 * c.mass * r * r);
        c.pebbles = {{Vec3::Zero(), r}};
        sim.add_clump(c);
      } else {
        dem::SphereSpec s;
        s.position = x;
        s.velocity = v;
        s.angular_velocity = Vec3(0.0, 2.0, 1.0);
        s.radius = r;
        sim.add_sphere(s);
      }
    }
    sim.prepare();
    for (int k = 0; k < 5000; ++k) sim.step();
    return sim.bodies();
  };
  const dem::Bodies a = build(true), b = build(false);
  CHECK(a.position == b.position);
  CHECK(a.velocity == b.velocity);
  CHECK(a.angular_velocity == b.angular_velocity);
}
