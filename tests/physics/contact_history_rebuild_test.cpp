// Contact springs across neighbour-list rebuilds. The list's skin is a performance setting: it
// decides how often the list is rebuilt, never what the contacts do. Reference: the same run
// with a skin so large that the list is rebuilt only every ~800 steps.
//
// Scene: 18 spheres in a closed box, high friction (mu = 10, so the tangential spring sticks
// and is still loaded when a contact opens) and rolling resistance, colliding about 75 times in
// 0.1 s. A contact that opens must release its springs (their energy is booked as dissipated)
// and forget them. The skins range from half of a step's move (a rebuild every step, an opened
// pair dropped from the list at once) to a few hundred steps' moves. Before the fix a contact
// opening on the step after a rebuild kept its springs and booked nothing: the friction account
// came out up to 10 % low at the smallest skins.
//
// Tolerance 1e-12 relative: without periodic wraps the arithmetic of every pair is the same at
// any skin; only the order in which released energies are summed differs, by rounding. (In a
// periodic box the wraps, x + L - L, also round, and sticking collisions amplify that by about
// 1e5 over 75 collisions: this check needs the walled box.)
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "tests/physics/scene_helpers.hpp"

using namespace mfdem;
using namespace mfdem::test;

namespace {

constexpr double kRadius = 0.02, kBox = 0.2;  // m
constexpr double kStep = 2e-6;                // s; 0.1 of 2/w_t for ks = 1e7 N/m in series
constexpr int kSteps = 50'000;
constexpr int kSpheres = 18;

struct RunResult {
  std::vector<Vec3> velocity, spin;
  double friction = 0.0;  // J, dissipated by slip and released springs
  int contact_starts = 0;
  std::int64_t rebuilds = 0;
};

RunResult run_collisions(double skin) {
  dem::Material m = make_material("stone", 2e7, 2e7, 10.0, 0.0);
  m.rolling_friction = 0.3;
  dem::SimulationSettings settings = fixed_step(kStep);
  settings.skin = skin;
  dem::Simulation sim(box_domain(Vec3::Zero(), Vec3::Constant(kBox)), one_material(m), settings);
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < kSpheres; ++k) {  // a 3 x 3 x 2 lattice of pitch 0.066 m, 0.1 m
    const Vec3 position(0.033 + 0.066 * (k % 3), 0.033 + 0.066 * (k / 3 % 3), 0.05 + 0.1 * (k / 9));
    sim.add_sphere(sphere(position, kRadius, 0, 2.0 * Vec3(u(rng), u(rng), u(rng)),
                          40.0 * Vec3(u(rng), u(rng), u(rng))));
  }
  for (const auto& w : dem::box_walls("box", Vec3::Zero(), Vec3::Constant(kBox), false, 0)) sim.add_wall(w);
  sim.prepare();
  RunResult r;
  dem::Index previous = 0;
  for (int k = 0; k < kSteps; ++k) {
    sim.step();
    const dem::Index now = sim.active_contact_count();
    r.contact_starts += static_cast<int>(std::max<dem::Index>(0, now - previous));
    previous = now;
  }
  for (dem::Index b = 0; b < kSpheres; ++b) {
    r.velocity.push_back(sim.bodies().velocity[b]);
    r.spin.push_back(sim.bodies().angular_velocity[b]);
  }
  r.friction = sim.energy().dissipated_friction;
  r.rebuilds = sim.neighbour_rebuilds();
  return r;
}

}  // namespace

TEST_CASE("contact springs and their released energy do not depend on how often the neighbour list is rebuilt",
          "[physics][contact][neighbor]") {
  const SerialThreads serial;
  const RunResult reference = run_collisions(0.01);
  REQUIRE(reference.contact_starts >= 50);  // the scene does collide, again and again
  REQUIRE(reference.friction > 0.0);
  const double move_per_step = 3.5 * kStep;  // m, about the fastest body's move in one step
  for (const double skin : {0.5 * move_per_step, 1.5 * move_per_step, 5.0 * move_per_step, 17.0 * move_per_step,
                            60.0 * move_per_step, 200.0 * move_per_step}) {
    CAPTURE(skin);
    const RunResult r = run_collisions(skin);
    CHECK(r.rebuilds > 5 * reference.rebuilds);  // the skin did force many more rebuilds
    CHECK(r.contact_starts == reference.contact_starts);
    CHECK(r.friction == Approx(reference.friction).epsilon(1e-12));
    for (int b = 0; b < kSpheres; ++b) {
      const double v_scale = reference.velocity[b].norm(), w_scale = reference.spin[b].norm();
      CHECK((r.velocity[b] - reference.velocity[b]).norm() <= 1e-12 * v_scale);
      CHECK((r.spin[b] - reference.spin[b]).norm() <= 1e-12 * w_scale);
    }
  }
}
