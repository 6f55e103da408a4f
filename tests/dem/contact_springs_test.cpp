// Saving and restoring contact springs (Simulation::contact_springs / set_initial_springs).
//
// Reference: a sphere at rest on an incline of angle th (gravity tilted, g (sin th, 0, -cos th))
// with tan th below the rolling resistance mu_r: statics says its shear spring holds
// m g sin th and its rolling spring R m g sin th, and the net force on it is zero. A new
// simulation of the same state that restores the springs must start in that equilibrium; one
// that does not starts with the whole downhill weight m g sin th unbalanced.
#include <catch2/catch.hpp>

#include <cmath>

#include "dem/simulation.hpp"
#include "tests/dem/builders.hpp"

using namespace mfdem::dem_test;
using mfdem::dem::SpringState;

namespace {

constexpr double kRadius = 0.02;
constexpr double kTheta = 0.15;  // rad: tan = 0.151, below mu_r = 0.3 and mu = 0.5

mfdem::dem::Simulation sphere_on_incline(const Vec3& position, const Vec3& velocity, const Vec3& spin) {
  const MaterialParameters ballast{"ballast", 2e7, 0.5, 0.3, 0.2, 0.7};
  mfdem::dem::Simulation sim(box_domain(Vec3(-1.0, -1.0, -0.1), Vec3(1.0, 1.0, 1.0)), material_table({ballast}),
                             settings(kGravity * Vec3(std::sin(kTheta), 0.0, -std::cos(kTheta))));
  sim.add_wall(floor_wall(0));
  mfdem::dem::SphereSpec s;
  s.position = position;
  s.velocity = velocity;
  s.angular_velocity = spin;
  s.radius = kRadius;
  sim.add_sphere(s);
  return sim;
}

}  // namespace

TEST_CASE("restored springs resume a sphere's equilibrium on an incline, and without them the weight is unbalanced",
          "[dem][springs]") {
  // Settle the sphere (local damping 0.7, viscous 0.2) for 0.3 s: it comes to rest, sticking.
  mfdem::dem::Simulation settle = sphere_on_incline(Vec3(0.0, 0.0, kRadius - 1e-6), Vec3::Zero(), Vec3::Zero());
  settle.prepare();
  while (settle.time() < 0.3) settle.step();
  const double weight = sphere_mass(kRadius) * kGravity;
  const double downhill = weight * std::sin(kTheta);
  REQUIRE(settle.bodies().velocity[0].norm() < 1e-5);
  REQUIRE(settle.bodies().unbalanced_force[0].norm() < 1e-4 * weight);

  const std::vector<SpringState> springs = settle.contact_springs();
  REQUIRE(springs.size() == 1);
  CHECK(springs[0].kind == SpringState::Kind::kWall);
  // Statics: the shear spring holds the downhill weight (tolerance: the 1e-4 residual above).
  CHECK(springs[0].history.shear_force.norm() == Approx(downhill).epsilon(1e-3));

  const auto& b = settle.bodies();
  mfdem::dem::Simulation resumed = sphere_on_incline(b.position[0], b.velocity[0], b.angular_velocity[0]);
  resumed.set_initial_springs(springs);
  resumed.prepare();
  mfdem::dem::Simulation restarted = sphere_on_incline(b.position[0], b.velocity[0], b.angular_velocity[0]);
  restarted.prepare();
  CAPTURE(downhill, resumed.bodies().unbalanced_force[0].norm(), restarted.bodies().unbalanced_force[0].norm());
  CHECK(resumed.bodies().unbalanced_force[0].norm() < 1e-3 * downhill);
  CHECK(restarted.bodies().unbalanced_force[0].norm() == Approx(downhill).epsilon(1e-3));
  // And the resumed sphere stays where it was: after 0.05 s it has moved less than 1e-9 m.
  while (resumed.time() < 0.05) resumed.step();
  CHECK((resumed.bodies().position[0] - b.position[0]).norm() < 1e-9);
}

TEST_CASE("springs that do not belong to the bed are refused with a message", "[dem][springs]") {
  mfdem::dem::Simulation sim = sphere_on_incline(Vec3(0.0, 0.0, kRadius), Vec3::Zero(), Vec3::Zero());
  SpringState bad;
  bad.kind = SpringState::Kind::kWall;
  bad.first = 0;
  bad.second = 3;  // there is one wall
  sim.set_initial_springs({bad});
  CHECK_THROWS_WITH(sim.prepare(), Catch::Matchers::Contains("initial spring (element and wall 0, 3): wall out of range (0-0)"));
}
