// The settling stage's creep criterion (studies/railway/stage_runner.hpp): the stones' mean
// displacement over a window, over their mean size. Reference: balls drifting at a constant
// speed in zero gravity with no contact, whose displacement over a time t is exactly v t, and
// whose force ratio (no contact: infinite) can never end the stage.
#include <catch2/catch.hpp>

#include <cmath>

#include "studies/railway/stage_runner.hpp"
#include "tests/dem/builders.hpp"

namespace {

using mfdem::dem::Simulation;
using mfdem::dem::Vec3;
using mfdem::railway::CreepGoal;
using mfdem::railway::RestCriterion;
using mfdem::railway::run_until_settled;
using namespace mfdem::dem_test;

constexpr double kSpeed = 1e-3;       // m/s
constexpr double kSize = 0.04;        // m, the length scale of the creep
constexpr double kWindow = 0.01;      // s
constexpr double kCheck = 1e-3;       // s between checks
constexpr double kMaxTime = 0.05;     // s
constexpr double kEnergyScale = 1e6;  // J: the kinetic condition always holds

// Two balls drifting along y at kSpeed, one of them across the periodic face y = 0.2.
Simulation drifting_balls() {
  Simulation sim(box_domain(Vec3::Zero(), Vec3(0.2, 0.2, 0.2), {false, true, false}),
                 material_table({MaterialParameters{}}), settings(Vec3::Zero(), 1e-5));
  sim.add_sphere(sphere(Vec3(0.05, 0.1, 0.1), 0.01, 0, Vec3(0.0, kSpeed, 0.0)));
  sim.add_sphere(sphere(Vec3(0.15, 0.2 - 2e-5, 0.1), 0.01, 0, Vec3(0.0, kSpeed, 0.0)));
  sim.prepare();
  return sim;
}

// The drifting balls settled with checks every kCheck up to kMaxTime.
mfdem::railway::StageReport settle(const CreepGoal& goal, double energy_scale = kEnergyScale) {
  Simulation sim = drifting_balls();
  return run_until_settled(sim, "settle", 1e-3, energy_scale, kMaxTime, true, RestCriterion::kForcesAndEnergy, nullptr,
                           0.02, kCheck, {}, goal);
}

}  // namespace

TEST_CASE("the creep of drifting balls is v t over the length scale, across a periodic face too",
          "[railway][settling]") {
  // A target below the drift's creep: the stage runs to its limit, measuring at every check.
  const auto r = settle({0.5 * kSpeed * kWindow / kSize, kWindow, kSize});
  CHECK_FALSE(r.settled);
  REQUIRE(r.check_creep.size() == r.check_time.size());
  REQUIRE(r.check_creep.size() == 50);
  for (std::size_t k = 0; k < r.check_creep.size(); ++k) {
    // Before a window has passed: the displacement since the first check, one check interval
    // after the start; then over the whole window. Rounding: 1e-9 relative.
    const double span = std::min(r.check_time[k] - r.check_time[0], kWindow);
    CAPTURE(k, r.check_time[k]);
    CHECK(r.check_creep[k] == Approx(kSpeed * span / kSize).epsilon(1e-9).margin(1e-15));
  }
}

TEST_CASE("a stage ends by creep once a full window moved less than the target, and only then",
          "[railway][settling]") {
  const CreepGoal goal{1.5 * kSpeed * kWindow / kSize, kWindow, kSize};
  const auto r = settle(goal);
  CHECK(r.settled);
  CHECK(r.settled_by_creep);
  // The first check at which the kept positions span the window: the window after the first check.
  CHECK(r.simulated_time == Approx(kCheck + kWindow).epsilon(1e-9));

  // Without a creep goal the same stage never settles (no contact: the force ratio is infinite).
  const auto p = settle(CreepGoal{});
  CHECK_FALSE(p.settled);
  CHECK(p.check_creep.empty());
  CHECK(p.simulated_time == Approx(kMaxTime).epsilon(1e-9));

  // The kinetic condition still applies: with a tiny energy scale the creep alone does not end it.
  const auto m = settle(goal, 1e-20);
  CHECK_FALSE(m.settled);
}
