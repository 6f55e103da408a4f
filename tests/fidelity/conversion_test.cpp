// The clump-to-ball conversion of a bed: what it keeps (stones, mass, centres, velocities, the
// springs of untouched contacts), the ball it makes (the sphere of equal volume), and the
// geometry a policy measures (height, gap to the sleeper across a periodic face).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "fidelity/conversion.hpp"

using namespace mfdem::fidelity;
using mfdem::dem::ClumpSpec;
using mfdem::dem::SpringState;
using mfdem::dem::Vec3;

namespace {

constexpr double kDensity = 2800.0;
constexpr int kStone = 0, kBall = 3;

// A two-pebble clump along x whose mass is that of `volume` m^3 of stone.
ClumpSpec clump_at(const Vec3& x, double volume) {
  ClumpSpec c;
  c.position = x;
  c.velocity = Vec3(0.1, -0.2, 0.3);
  c.angular_velocity = Vec3(1.0, 2.0, 3.0);
  c.mass = kDensity * volume;
  c.principal_inertia = Vec3(1e-6, 2e-6, 2e-6);
  c.pebbles = {{Vec3(-0.01, 0, 0), 0.015}, {Vec3(0.01, 0, 0), 0.015}};
  c.material = kStone;
  return c;
}

BedFrame bed_frame() {
  BedFrame f;
  f.sleeper.centre = Vec3(0.0, 0.3, 0.335);
  f.sleeper.half_extent = Vec3(0.5, 0.1, 0.035);  // base at 0.30 m
  f.domain.min = Vec3(-1, 0, -0.05);
  f.domain.max = Vec3(1, 0.6, 1);
  f.domain.periodic = {false, true, false};
  return f;
}

SpringState pair_spring(int a, int b, double marker) {
  SpringState s;
  s.first = a;
  s.second = b;
  s.history.shear_force = Vec3(marker, 0, 0);
  return s;
}

}  // namespace

TEST_CASE("a ball replaces a clump by the sphere of equal volume at its centre of mass", "[fidelity][conversion]") {
  const double volume = 2.0e-5;
  const ClumpSpec c = clump_at(Vec3(0.1, 0.2, 0.05), volume);
  const ClumpSpec b = ball_of(c, kDensity, kBall);
  REQUIRE(b.pebbles.size() == 1);
  // 4/3 pi r^3 = V
  CHECK(4.0 / 3.0 * std::numbers::pi * std::pow(b.pebbles[0].radius, 3) == Approx(volume).epsilon(1e-14));
  CHECK(b.pebbles[0].offset == Vec3::Zero());
  CHECK(b.mass == c.mass);
  CHECK(b.position == c.position);
  CHECK(b.velocity == c.velocity);
  CHECK(b.material == kBall);
  // Solid sphere: I = 2/5 m r^2 about every axis.
  const double inertia = 0.4 * c.mass * b.pebbles[0].radius * b.pebbles[0].radius;
  CHECK(b.principal_inertia.x() == Approx(inertia).epsilon(1e-15));
  CHECK(b.principal_inertia.z() == b.principal_inertia.x());
}

TEST_CASE("a clump of one centred pebble is already its ball: kept bitwise", "[fidelity][conversion]") {
  ClumpSpec c = clump_at(Vec3(0.1, 0.2, 0.05), 1e-5);
  c.pebbles = {{Vec3::Zero(), 0.0123}};
  const ClumpSpec b = ball_of(c, kDensity, kBall);
  CHECK(b.pebbles[0].radius == 0.0123);
  CHECK(b.mass == c.mass);
  CHECK(b.principal_inertia == c.principal_inertia);
  CHECK(b.orientation.coeffs() == c.orientation.coeffs());
}

TEST_CASE("a policy measures height above the floor and the gap to the sleeper, across a periodic face",
          "[fidelity][conversion]") {
  const BedFrame f = bed_frame();
  CHECK(f.scale().sleeper_base == Approx(0.30).epsilon(1e-14));
  ClumpSpec s = clump_at(Vec3(0.0, 0.3, 0.2), 1e-5);  // under the sleeper: base 0.30, pebble tops at 0.215
  StoneGeometry g = measure_stone(s, f);
  CHECK(g.height == 0.2);
  CHECK(g.sleeper_gap == Approx(0.30 - 0.215).epsilon(1e-12));
  // Beyond the sleeper end along x: the nearer pebble's centre at x = 0.55, 0.05 from the end face.
  s.position = Vec3(0.56, 0.3, 0.33);
  CHECK(measure_stone(s, f).sleeper_gap == Approx(0.05 - 0.015).epsilon(1e-12));
  // A sleeper near the periodic face y = 0 (spanning -0.05..0.15 m): a stone at y = 0.58 lies
  // beside its image (0.55..0.75), so only the x gap counts.
  BedFrame edge = f;
  edge.sleeper.centre.y() = 0.05;
  s.position = Vec3(0.56, 0.58, 0.33);
  CHECK(measure_stone(s, edge).sleeper_gap == Approx(0.05 - 0.015).epsilon(1e-12));
  // Touching or overlapping counts as 0.
  s.position = Vec3(0.0, 0.3, 0.29);
  CHECK(measure_stone(s, f).sleeper_gap == 0.0);
}

TEST_CASE("converting a bed keeps its stones, mass and centres, and the springs of untouched contacts",
          "[fidelity][conversion]") {
  // Stones at heights 0.05, 0.10, 0.20, 0.25 m, two pebbles each (elements 0-7).
  std::vector<ClumpSpec> bed;
  for (double z : {0.05, 0.10, 0.20, 0.25}) bed.push_back(clump_at(Vec3(0.0, 0.3, z), 1.5e-5));
  std::vector<SpringState> springs = {pair_spring(0, 2, 1), pair_spring(1, 5, 2), pair_spring(4, 6, 3),
                                      pair_spring(5, 7, 4)};
  SpringState box;
  box.kind = SpringState::Kind::kBox;
  box.first = 7;
  box.second = 0;
  springs.push_back(box);
  const Policy layer = PolicyRegistry::builtin().make("layer-by-height:h=0.15", bed_frame().scale());
  const ConvertedBed out = convert_bed(bed, springs, layer, bed_frame(), kDensity, kBall);
  REQUIRE(out.bodies.size() == bed.size());
  CHECK(out.converted == 2);
  CHECK(out.balls == 2);
  CHECK(out.clumps == 2);
  CHECK(out.elements_before == 8);
  CHECK(out.elements_after == 6);  // 1 + 1 + 2 + 2
  double mass_before = 0.0, mass_after = 0.0;
  for (std::size_t k = 0; k < bed.size(); ++k) {
    mass_before += bed[k].mass;
    mass_after += out.bodies[k].mass;
    CHECK(out.bodies[k].position == bed[k].position);
  }
  CHECK(mass_after == mass_before);
  CHECK(out.bodies[0].material == kBall);
  CHECK(out.bodies[2].material == kStone);
  CHECK(out.bodies[2].pebbles.size() == 2);
  // Stones 0 and 1 (elements 0-3) changed: springs touching them go; 4-7 become 2-5.
  CHECK(out.springs_dropped == 2);
  REQUIRE(out.springs.size() == 3);
  CHECK(out.springs[0].first == 2);
  CHECK(out.springs[0].second == 4);
  CHECK(out.springs[0].history.shear_force.x() == 3);
  CHECK(out.springs[1].first == 3);
  CHECK(out.springs[1].second == 5);
  CHECK(out.springs[2].kind == SpringState::Kind::kBox);
  CHECK(out.springs[2].first == 5);
  CHECK(out.springs[2].second == 0);  // a box index, not an element
}

TEST_CASE("all-clump leaves a bed and its springs bitwise unchanged, and balls stay balls", "[fidelity][conversion]") {
  std::vector<ClumpSpec> bed;
  for (double z : {0.05, 0.25}) bed.push_back(clump_at(Vec3(0.0, 0.3, z), 1.5e-5));
  bed[0] = ball_of(bed[0], kDensity, kBall);
  const std::vector<SpringState> springs = {pair_spring(0, 1, 1), pair_spring(1, 2, 2)};
  const ConvertedBed out = convert_bed(bed, springs, PolicyRegistry::builtin().make("all-clump", {0.3}),
                                       bed_frame(), kDensity, kBall);
  CHECK(out.converted == 0);
  CHECK(out.balls == 1);  // the ball it was given
  CHECK(out.springs_dropped == 0);
  REQUIRE(out.springs.size() == 2);
  CHECK(out.springs[1].first == 1);
  CHECK(out.springs[1].second == 2);
  for (std::size_t k = 0; k < bed.size(); ++k) {
    CHECK(out.bodies[k].pebbles.size() == bed[k].pebbles.size());
    CHECK(out.bodies[k].pebbles[0].radius == bed[k].pebbles[0].radius);
    CHECK(out.bodies[k].material == bed[k].material);
  }
}
