// Periodic boundaries: a body leaving through a periodic face re-enters through the opposite
// one, and contacts reach across the faces through the nearest image. Reference: the same motion
// in an unbounded (larger, non-periodic) domain, or the same collision in the middle of the box.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <vector>

#include "tests/dem/builders.hpp"

namespace {

using mfdem::dem::Simulation;
using mfdem::dem::Vec3;
using namespace mfdem::dem_test;

constexpr double kBox = 1.0;  // m, edge of the periodic box [0, 1]^3

// Shortest periodic difference a - b along every axis of a box of edge kBox.
Vec3 periodic_difference(const Vec3& a, const Vec3& b) {
  Vec3 d = a - b;
  for (int k = 0; k < 3; ++k) d[k] -= kBox * std::round(d[k] / kBox);
  return d;
}

}  // namespace

TEST_CASE("a sphere crossing periodic faces keeps its velocity and its unwrapped path matches an open domain",
          "[dem][periodic]") {
  // In 0.04 s it moves 1.2 m along x (crossing x = 1 twice), -0.68 m along y (crossing y = 0
  // once) and 0.16 m along z (not crossing).
  const Vec3 start(0.9, 0.2, 0.5), velocity(30.0, -17.0, 4.0);
  const double radius = 0.02;
  auto make = [&](const mfdem::dem::Domain& domain) {
    Simulation sim(domain, material_table({MaterialParameters{}}), settings(Vec3::Zero()));
    sim.add_sphere(sphere(start, radius, 0, velocity, Vec3(0, 0, 5.0)));
    sim.prepare();
    return sim;
  };
  Simulation periodic = make(box_domain(Vec3::Zero(), Vec3::Constant(kBox), {true, true, true}));
  // Large enough for the whole path (the cell grid of the neighbour search spans the domain, so a
  // needlessly large one only costs time).
  Simulation open = make(box_domain(Vec3(0.0, -0.6, 0.0), Vec3(2.2, 1.0, 1.0)));

  Vec3 unwrapped = periodic.bodies().position[0];
  Vec3 previous = unwrapped;
  std::array<int, 3> wraps{0, 0, 0};
  Vec3 lowest = unwrapped, highest = unwrapped;
  double largest_gap = 0.0;
  bool same_velocity = true;
  REQUIRE(periodic.time_step() == open.time_step());
  const double dt = periodic.time_step();
  while (periodic.time() < 0.04) {
    periodic.step();
    open.step();
    const Vec3& now = periodic.bodies().position[0];
    // A jump by (about) one box length is a wrap; undo it to follow the open-domain path.
    const Vec3 jump = now - previous;
    for (int a = 0; a < 3; ++a)
      if (std::abs(jump[a]) > 0.5 * kBox) ++wraps[a];
    unwrapped += periodic_difference(now, previous);
    previous = now;
    largest_gap = std::max(largest_gap, (unwrapped - open.bodies().position[0]).norm());
    same_velocity = same_velocity && periodic.bodies().velocity[0] == velocity &&
                    periodic.bodies().angular_velocity[0] == open.bodies().angular_velocity[0];
    lowest = lowest.cwiseMin(now), highest = highest.cwiseMax(now);
  }
  CHECK(wraps == std::array<int, 3>{2, 1, 0});
  // Wrapping waits for the next neighbour-list build (a move of half the skin), never longer.
  // The automatic skin of a body flying at 35 m/s is at its ceiling, five times the base
  // 0.2 x 0.02 m: half of it is 10 mm.
  CAPTURE(lowest, highest);
  CHECK(lowest.minCoeff() >= -1e-2 - velocity.norm() * dt);
  CHECK(highest.maxCoeff() < kBox + 1e-2 + velocity.norm() * dt);
  // No force acts: the velocity is carried over bit for bit.
  CHECK(same_velocity);
  // Tolerance: the two runs add the same increments dt v to coordinates that differ by a box
  // length (1 m), so they round differently, by at most half an ulp of 1 m (1.1e-16 m) per step
  // and axis: the 2700 steps give < 1e-12 m.
  CAPTURE(largest_gap);
  CHECK(largest_gap <= 1e-12);
}

// An oblique collision with friction, rolling resistance and damping, once in the middle of the
// box and once straddling the x, y and z faces (the sphere centres on opposite sides, so the
// contact is found through an image; one centre crosses the x face during the contact, and a
// small skin rebuilds the neighbour list, carrying the spring history, every few steps).
TEST_CASE("a collision across the periodic faces gives the same result as in the middle of the box",
          "[dem][periodic]") {
  MaterialParameters p;
  p.friction = 0.5;
  p.rolling_friction = 0.3;
  p.damping_ratio = 0.3;
  const double ra = 0.05, rb = 0.04;
  const Vec3 separation(0.1, 0.02, -0.015);  // gap 0.013 m, closed at about 16 ms
  const Vec3 va(2.0, 0.3, 0.1), vb(1.2, -0.2, 0.3);
  const Vec3 wa(5.0, -3.0, 10.0), wb(-8.0, 2.0, 1.0);

  auto run = [&](const Vec3& a) {
    auto s = settings(Vec3::Zero());
    s.skin = 1e-3;  // m: the list is rebuilt whenever a sphere has moved 0.5 mm
    Simulation sim(box_domain(Vec3::Zero(), Vec3::Constant(kBox), {true, true, true}),
                   material_table({p}), s);
    sim.add_sphere(sphere(a, ra, 0, va, wa));
    sim.add_sphere(sphere(a + separation, rb, 0, vb, wb));
    sim.prepare();
    int steps_in_contact = 0;
    while (sim.time() < 0.04) {
      sim.step();
      steps_in_contact += sim.active_contact_count() > 0;
    }
    CHECK(steps_in_contact > 20);
    return sim;
  };
  const Vec3 middle(0.40, 0.45, 0.52);
  // The centre of a reaches x = 1 about 1 ms after the contact begins.
  const Vec3 straddling(0.967, 0.985, 0.99);
  const Simulation inside = run(middle);
  const Simulation across = run(straddling);
  REQUIRE(inside.step_count() == across.step_count());
  REQUIRE(across.neighbour_rebuilds() > 50);

  // The collision did something: each sphere's velocity changed by more than 0.1 m/s.
  CHECK((inside.bodies().velocity[0] - va).norm() > 0.1);
  CHECK((inside.bodies().velocity[1] - vb).norm() > 0.1);

  // Reference for the tolerance: the same collision translated inside the box. Not bitwise:
  // runs at different places compute the centre differences from coordinates of different
  // magnitude, so they round differently (~1e-16 m on overlaps of ~1e-4 m: 1e-12 relative per
  // step), and through the stick and slip of the tangential and rolling springs over the ~25
  // steps of contact this grows to ~1e-11 relative on the spins (measured: 2.4e-11 between the
  // two interior runs, 1.7e-11 between the interior and the periodic run; 1e-12 to 3e-12 on
  // the velocities). Tolerance 1e-10 relative to each velocity and spin: a few times rounding;
  // a spring history lost at a wrap for one step (Ft dt / m ~ 1e-2 m/s) or a wrong image would
  // be 1e8 times larger. Positions: 1e-12 m.
  const Simulation elsewhere = run(middle - Vec3::Constant(0.3));
  auto relative_difference = [](const Simulation& a, const Simulation& b) {
    double worst = 0.0;
    for (int k = 0; k < 2; ++k) {
      worst = std::max(worst, (a.bodies().velocity[k] - b.bodies().velocity[k]).norm() /
                                  a.bodies().velocity[k].norm());
      worst = std::max(worst, (a.bodies().angular_velocity[k] - b.bodies().angular_velocity[k]).norm() /
                                  a.bodies().angular_velocity[k].norm());
    }
    return worst;
  };
  const double rounding = relative_difference(inside, elsewhere);
  const double periodic = relative_difference(inside, across);
  double position_difference = 0.0;
  for (int b = 0; b < 2; ++b)
    position_difference = std::max(position_difference,
                                   periodic_difference(across.bodies().position[b],
                                                       inside.bodies().position[b] + straddling - middle)
                                       .norm());
  CAPTURE(rounding, periodic, position_difference);
  CHECK(rounding <= 1e-10);
  CHECK(periodic <= 1e-10);
  CHECK(position_difference <= 1e-12);
}

TEST_CASE("the nearest periodic image of a separation is within half a period", "[dem][periodic]") {
  // Reference: minimum-image convention; a box 0.6 m periodic along y only. Exact in binary
  // for these values except the 0.55 case, where round-off of one subtraction is allowed.
  mfdem::dem::Domain d;
  d.min = mfdem::dem::Vec3(-1.0, 0.0, 0.0);
  d.max = mfdem::dem::Vec3(1.0, 0.6, 1.0);
  d.periodic = {false, true, false};
  const auto image = d.nearest_image(mfdem::dem::Vec3(1.5, 0.55, -0.9));
  CHECK(image.x() == 1.5);   // not periodic: unchanged
  CHECK(image.z() == -0.9);
  CHECK(image.y() == Approx(-0.05).margin(1e-15));
  CHECK(d.nearest_image(mfdem::dem::Vec3(0.0, -0.5, 0.0)).y() == Approx(0.1).margin(1e-15));
  CHECK(d.nearest_image(mfdem::dem::Vec3(0.0, 0.2, 0.0)).y() == 0.2);
}
