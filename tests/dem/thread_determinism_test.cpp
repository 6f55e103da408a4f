// Reproducibility whatever the thread count (design.md, "What fast means here"): every sum has an
// order fixed by fixed-size chunks (dem/chunked.hpp, 256 bodies per chunk) or by the pair list,
// so one, two and three threads must give the same bits, though the threads' blocks differ (and
// move with the measured load every 100 steps). Reference: the one-thread run; tolerance: none
// (memcmp).
#include <catch2/catch.hpp>
#include <omp.h>

#include <cstring>
#include <vector>

#include "dem/chunked.hpp"
#include "tests/dem/builders.hpp"

namespace {

using mfdem::dem::Simulation;
using mfdem::dem::Vec3;
using namespace mfdem::dem_test;

struct Outcome {
  std::vector<Vec3> position, velocity, angular_velocity, wall_force;
  mfdem::dem::EnergyReport energy;
  long long contacts = 0, rebuilds = 0;
};

// 3000 spheres (twelve chunks of bodies) of radius 9.5-10.5 mm on a 20 mm lattice in a closed
// box: about half the neighbours start overlapping (up to 1 mm), so the bed is crowded with
// contacts from the first step, and the spheres are thrown about at up to 0.5 m/s. Every
// channel is on: friction, rolling resistance, viscous and local damping. 500 steps: the cost of
// a threaded run on a busy machine grows with the number of parallel regions (steps), not with
// the bodies, and 500 steps already hold many neighbour-list rebuilds.
Outcome run_bed(int threads) {
  omp_set_num_threads(threads);
  MaterialParameters grain;
  grain.stiffness = 1e7;
  grain.friction = 0.5;
  grain.rolling_friction = 0.3;
  grain.damping_ratio = 0.3;
  grain.local_damping = 0.2;
  MaterialParameters wall = grain;
  wall.name = "wall";
  constexpr double pitch = 0.02;
  const std::array<int, 3> cells{15, 15, 14};
  const Vec3 box(cells[0] * pitch, cells[1] * pitch, cells[2] * pitch);
  Simulation sim(box_domain(Vec3::Zero(), box), material_table({grain, wall}),
                 settings(Vec3(0, 0, -kGravity)));
  for (const auto& s : lattice(cells, Vec3::Zero(), pitch, 0.0095, 0.0105, 0.5, 2024, 0, 3000))
    sim.add_sphere(s);
  for (const auto& w : mfdem::dem::box_walls("box", Vec3::Zero(), box, false, 1)) sim.add_wall(w);
  sim.prepare();
  for (int k = 0; k < 500; ++k) sim.step();

  Outcome out;
  out.position = sim.bodies().position;
  out.velocity = sim.bodies().velocity;
  out.angular_velocity = sim.bodies().angular_velocity;
  for (int w = 0; w < static_cast<int>(sim.walls().size()); ++w) out.wall_force.push_back(sim.wall_force(w));
  out.energy = sim.energy();
  out.contacts = sim.active_contact_count();
  out.rebuilds = sim.neighbour_rebuilds();
  return out;
}

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

}  // namespace

TEST_CASE("one, two and three threads give bitwise identical trajectories and wall forces", "[dem][threads]") {
  const int previous = omp_get_max_threads();
  const Outcome one = run_bed(1);
  const Outcome two = run_bed(2);
  const Outcome three = run_bed(3);  // uneven blocks: more threads than this machine's cores
  omp_set_num_threads(previous);

  // The scene is the one the claim is about: more than one chunk of bodies, many contacts, and
  // neighbour-list rebuilds (which run threaded too).
  REQUIRE(one.position.size() == 3000);
  CHECK(static_cast<long long>(one.position.size()) > 2 * mfdem::dem::kChunkSize);
  CAPTURE(one.contacts, one.rebuilds);
  CHECK(one.contacts > 3000);
  CHECK(one.rebuilds > 1);

  CHECK(same_bits(one.position, two.position));
  CHECK(same_bits(one.velocity, two.velocity));
  CHECK(same_bits(one.angular_velocity, two.angular_velocity));
  CHECK(same_bits(one.wall_force, two.wall_force));
  CHECK(one.contacts == two.contacts);
  CHECK(one.rebuilds == two.rebuilds);
  CHECK(std::memcmp(&one.energy, &two.energy, sizeof(one.energy)) == 0);

  CHECK(same_bits(one.position, three.position));
  CHECK(same_bits(one.velocity, three.velocity));
  CHECK(same_bits(one.angular_velocity, three.angular_velocity));
  CHECK(same_bits(one.wall_force, three.wall_force));
  CHECK(std::memcmp(&one.energy, &three.energy, sizeof(one.energy)) == 0);
}
