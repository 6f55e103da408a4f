// Rigid boxes (sleepers): contact geometry, a free axis under load, and the work of a drive.
#include <catch2/catch.hpp>

#include <cmath>

#include "dem/rigid_box.hpp"
#include "dem/simulation.hpp"

using namespace mfdem;
using dem::Vec3;

TEST_CASE("sphere-box contact geometry matches the closed forms at a face, an edge and inside",
          "[box][geometry]") {
  // Reference: distance from a point to an axis-aligned box; exact up to round-off (1e-15).
  const Vec3 centre(1.0, 2.0, 3.0), half(0.5, 0.25, 0.1);
  SECTION("face") {
    const auto c = dem::sphere_box_contact(Vec3(1.2, 2.0, 3.1 + 0.08), 0.1, centre, half);
    REQUIRE(c);
    CHECK(c->overlap == Approx(0.02).margin(1e-15));
    CHECK((c->normal - Vec3::UnitZ()).norm() < 1e-15);
  }
  SECTION("edge") {
    const Vec3 x(1.5 + 0.03, 2.25 + 0.04, 3.0);  // 0.05 from the edge along (3, 4, 0)/5
    const auto c = dem::sphere_box_contact(x, 0.06, centre, half);
    REQUIRE(c);
    CHECK(c->overlap == Approx(0.01).margin(1e-15));
    CHECK((c->normal - Vec3(0.6, 0.8, 0.0)).norm() < 1e-15);
  }
  SECTION("apart") { CHECK_FALSE(dem::sphere_box_contact(Vec3(1.0, 2.0, 3.3), 0.1, centre, half)); }
  SECTION("centre inside leaves through the nearest face") {
    const auto c = dem::sphere_box_contact(Vec3(1.0, 2.2, 3.0), 0.02, centre, half);
    REQUIRE(c);
    CHECK(c->overlap == Approx(0.02 + 0.05).margin(1e-15));
    CHECK((c->normal - Vec3::UnitY()).norm() < 1e-15);
  }
}

namespace {

dem::MaterialTable stone_and_concrete(double friction) {
  dem::MaterialTable t;
  dem::Material stone;
  stone.name = "stone";
  stone.normal_stiffness = stone.shear_stiffness = 2e6;
  stone.friction = friction;
  stone.damping_ratio = 0.5;
  stone.local_damping = 0.5;
  t.add(stone);
  dem::Material concrete = stone;
  concrete.name = "concrete";
  concrete.normal_stiffness = concrete.shear_stiffness = 5e9;
  t.add(concrete);
  return t;
}

constexpr double kBoxMass = 2.0;      // kg
constexpr double kSphereRadius = 0.02;  // m

// Four spheres on a concrete floor and a box free along z over them, its base `gap` above their
// tops, under a downward load (N).
dem::Simulation box_on_four_spheres(double gap, double load) {
  dem::Domain domain;
  domain.min = Vec3(-0.5, -0.5, 0.0);
  domain.max = Vec3(0.5, 0.5, 0.5);
  dem::Simulation sim(domain, stone_and_concrete(0.5), dem::SimulationSettings{});
  dem::PlaneWall floor;
  floor.material = 1;
  sim.add_wall(floor);
  const double r = kSphereRadius;
  for (int k = 0; k < 4; ++k) {
    dem::SphereSpec s;
    s.position = Vec3(k % 2 ? 0.05 : -0.05, k / 2 ? 0.05 : -0.05, r);
    s.radius = r;
    sim.add_sphere(s);
  }
  dem::RigidBox box;
  box.name = "sleeper";
  box.half_extent = Vec3(0.1, 0.1, 0.02);
  box.centre = Vec3(0.0, 0.0, 2.0 * r + 0.02 + gap);
  box.mass = kBoxMass;
  box.material = 1;
  box.driven = {true, true, false};
  box.applied_force = Vec3(0.0, 0.0, -load);
  sim.add_box(box);
  sim.prepare();
  return sim;
}

double total_mass(const dem::Simulation& sim) {
  double m = 0.0;
  for (double b : sim.bodies().mass) m += b;
  return m;
}

}  // namespace

TEST_CASE("a box free along z comes to rest on spheres, which carry its weight", "[box]") {
  // Reference: statics. At rest the spheres push the box up with M g and the floor carries
  // (M + sum m) g. Tolerance 1e-4 relative after 1 s with damping (residual oscillation).
  dem::Simulation sim = box_on_four_spheres(0.001, 0.0);
  const double sphere_mass = total_mass(sim);
  while (sim.time() < 1.0) sim.step();
  const double g = 9.81;
  CAPTURE(sim.box_force(0).z(), sim.wall_force(0).z(), sim.boxes()[0].velocity.z());
  CHECK(sim.box_force(0).z() == Approx(kBoxMass * g).epsilon(1e-4));
  CHECK(-sim.wall_force(0).z() == Approx((kBoxMass + sphere_mass) * g).epsilon(1e-4));
  CHECK(std::abs(sim.boxes()[0].velocity.z()) < 1e-4);
}

TEST_CASE("a load on a free box is carried by the spheres under it, and its work enters the energy balance",
          "[box][load]") {
  // Reference: statics, as above with the load P added: the spheres push the box up with
  // M g + P and the floor carries (M + sum m) g + P (1e-4 relative after 1 s with damping). The
  // box, set down touching, sinks by its two springs in series per sphere, ((M g + P) / 2 + m g)
  // / k (1e-3 relative), so the load does work P dz, which the energy account must hold:
  // |change of total| < 1 % of that work (the drive test's tolerance).
  const double load = 500.0;  // N, 25x the box's weight
  dem::Simulation sim = box_on_four_spheres(0.0, load);
  const double sphere_mass = total_mass(sim);
  const double e0 = sim.energy().total();
  const double z0 = sim.boxes()[0].centre.z();
  while (sim.time() < 1.0) sim.step();
  const double g = 9.81;
  const dem::EnergyReport e = sim.energy();
  const double sink = z0 - sim.boxes()[0].centre.z();
  CAPTURE(sim.box_force(0).z(), sim.wall_force(0).z(), sink, e.work_by_walls, e.total() - e0);
  CHECK(sim.box_force(0).z() == Approx(kBoxMass * g + load).epsilon(1e-4));
  CHECK(-sim.wall_force(0).z() == Approx((kBoxMass + sphere_mass) * g + load).epsilon(1e-4));
  const double k = 2e6 * 5e9 / (2e6 + 5e9);  // stone against concrete, in series
  const double per_sphere = (kBoxMass * g + load) / 4.0;
  CHECK(sink == Approx((2.0 * per_sphere + sphere_mass / 4.0 * g) / k).epsilon(1e-3));
  CHECK(e.work_by_walls == Approx(load * sink).epsilon(1e-9));
  CHECK(std::abs(e.total() - e0) < 0.01 * e.work_by_walls);
}

namespace {

// Five spheres in a row ahead of (+x of) a pusher box in zero gravity; the box moves at 0.5 m/s
// along x or, held still, grows its half length at 0.5 m/s: either way its +x face moves at
// 0.5 m/s.
dem::Simulation pusher_scene(bool grow) {
  dem::Domain domain;
  domain.min = Vec3(-1.0, -0.5, -0.5);
  domain.max = Vec3(1.0, 0.5, 0.5);
  dem::SimulationSettings settings;
  settings.gravity = Vec3::Zero();
  dem::Simulation sim(domain, stone_and_concrete(0.3), settings);
  for (int k = 0; k < 5; ++k) {
    dem::SphereSpec s;
    s.position = Vec3(0.05 + 0.045 * k, 0.003 * k, -0.002 * k);
    s.radius = 0.02;
    sim.add_sphere(s);
  }
  dem::RigidBox box;
  box.name = "pusher";
  box.half_extent = Vec3(0.02, 0.1, 0.1);
  box.centre = Vec3(0.0, 0.0, 0.0);
  box.mass = 100.0;
  box.material = 1;
  (grow ? box.growth_rate : box.velocity) = Vec3(0.5, 0.0, 0.0);
  sim.add_box(box);
  sim.prepare();
  return sim;
}

}  // namespace

TEST_CASE("the work of a driven box balances the energy it gives the spheres", "[box][energy]") {
  // Reference: energy balance, kinetic + elastic + dissipated = work done by the drive.
  // Tolerance: 1 % of the work, the (w dt)^2 accuracy of velocity Verlet's energy account at
  // the automatic step (measured error in the comment of the sphere energy tests: < 0.4 %).
  for (const bool grow : {false, true}) {
    dem::Simulation sim = pusher_scene(grow);
    const double e0 = sim.energy().total();
    while (sim.time() < 0.3) sim.step();
    const dem::EnergyReport e = sim.energy();
    CAPTURE(grow, e.work_by_walls, e.kinetic(), e.dissipated(), e.elastic, e.total() - e0);
    REQUIRE(e.work_by_walls > 0.0);
    CHECK(std::abs(e.total() - e0) < 0.01 * e.work_by_walls);
    // The pushed spheres end at least as fast as the box face (they are driven ahead of it).
    double slowest = 1e9;
    for (const auto& v : sim.bodies().velocity) slowest = std::min(slowest, v.x());
    CHECK(slowest > 0.0);
  }
}

TEST_CASE("a growing box pushes like a box moving at its face's speed", "[box][growth]") {
  // Reference: the +x face of a box growing its half length at rate r is, for the spheres
  // ahead of it, the same surface as that of a box of fixed size moving at r: same position
  // and velocity at every step (contact force, damping and friction see only these). The two
  // runs differ in the order of the floating-point sums (centre + half vs. half + centre);
  // 1e-9 m over 0.3 s of collisions allows for that round-off growing, and nothing more.
  dem::Simulation moving = pusher_scene(false), growing = pusher_scene(true);
  while (moving.time() < 0.3) moving.step(), growing.step();
  const double face_moving = moving.boxes()[0].centre.x() + moving.boxes()[0].half_extent.x();
  const double face_growing = growing.boxes()[0].centre.x() + growing.boxes()[0].half_extent.x();
  CHECK(face_growing == Approx(face_moving).epsilon(1e-12));
  CHECK(face_growing == Approx(0.02 + 0.5 * moving.time()).epsilon(1e-9));
  for (dem::Index b = 0; b < moving.bodies().size(); ++b) {
    CAPTURE(b);
    CHECK((moving.bodies().position[b] - growing.bodies().position[b]).norm() < 1e-9);
    CHECK((moving.bodies().velocity[b] - growing.bodies().velocity[b]).norm() < 1e-9);
  }
  CHECK((moving.box_force(0) - growing.box_force(0)).norm() < 1e-6 * (moving.box_force(0).norm() + 1.0));
}

TEST_CASE("a box meets a sphere across a periodic face as it meets it inside the box", "[box][periodic]") {
  // The same sphere resting 1 mm into the side of a box, once in the middle of a periodic axis
  // and once with the box at the face y = 0 (the sphere across it, at its unwrapped position
  // beyond the far face): the first evaluation gives the same force, kn x 1 mm along -y on the
  // box (kn in series, dem/material.hpp); the box straddles the face, the sphere lies near the
  // far face. Tolerance 1e-9 relative: round-off of the shift.
  dem::Domain domain;
  domain.min = Vec3(-0.5, 0.0, 0.0);
  domain.max = Vec3(0.5, 0.3, 0.5);
  domain.periodic = {false, true, false};
  auto force_on_box = [&](double box_y, double sphere_y) {
    dem::SimulationSettings settings;
    settings.gravity = Vec3::Zero();
    dem::Simulation sim(domain, stone_and_concrete(0.5), settings);
    dem::SphereSpec s;
    s.position = Vec3(0.0, sphere_y, 0.2);
    s.radius = 0.02;
    sim.add_sphere(s);
    dem::RigidBox box;
    box.name = "sleeper";
    box.half_extent = Vec3(0.1, 0.05, 0.02);
    box.centre = Vec3(0.0, box_y, 0.2);
    box.mass = 2.0;
    box.material = 1;
    sim.add_box(box);
    sim.prepare();
    return sim.box_force(0);
  };
  const Vec3 inside = force_on_box(0.15, 0.15 - 0.05 - 0.019);
  const Vec3 across = force_on_box(0.02, 0.3 + 0.02 - 0.05 - 0.019);  // box spans -0.03..0.07
  const double kn = 2e6 * 5e9 / (2e6 + 5e9);
  CHECK(inside.y() == Approx(kn * 1e-3).epsilon(1e-9));
  CHECK((across - inside).norm() < 1e-9 * inside.norm());
}

TEST_CASE("a box whose gap to its periodic image is narrower than an element is refused", "[box][periodic]") {
  // Reference: Simulation::check_boxes_clear_periodic_faces: gap = length - box length must
  // exceed the largest element diameter (0.04 m here).
  dem::Domain domain;
  domain.min = Vec3(-0.5, 0.0, 0.0);
  domain.max = Vec3(0.5, 0.3, 0.5);
  domain.periodic = {false, true, false};
  auto build = [&](double box_half_width) {
    dem::Simulation sim(domain, stone_and_concrete(0.5), dem::SimulationSettings{});
    dem::SphereSpec s;
    s.position = Vec3(0.3, 0.15, 0.1);
    s.radius = 0.02;
    sim.add_sphere(s);
    dem::RigidBox box;
    box.name = "sleeper";
    box.half_extent = Vec3(0.1, box_half_width, 0.02);
    box.centre = Vec3(0.0, 0.15, 0.2);
    box.mass = 2.0;
    box.material = 1;
    sim.add_box(box);
    sim.prepare();
  };
  CHECK_NOTHROW(build(0.15 - 0.021));  // a 0.042 m gap
  CHECK_THROWS_WITH(build(0.15 - 0.019),
                    Catch::Matchers::Contains("box 'sleeper' is 0.262 m long along the periodic axis y") &&
                        Catch::Matchers::Contains("0.038 m, must be wider than the largest element diameter 0.04 m"));
}

TEST_CASE("the force on a box is split by the face each contact leans on", "[box][faces]") {
  // Reference: Hooke's law at rest. A sphere pressed into each of four faces by 1 mm, one of
  // them into an edge of the +x end (normal (3, 0, 4)/5, counted to +z, its larger component).
  // At the first evaluation nothing moves, so each contact pushes the box by kn d along minus its
  // normal, kn = 2e6 x 5e9 / (2e6 + 5e9) (series); the faces add up to the total. Tolerance 1e-12
  // relative: round-off of one contact.
  dem::Domain domain;
  domain.min = Vec3(-1.0, -1.0, -1.0);
  domain.max = Vec3(1.0, 1.0, 1.0);
  dem::SimulationSettings settings;
  settings.gravity = Vec3::Zero();
  dem::Simulation sim(domain, stone_and_concrete(0.5), settings);
  const double r = 0.02, d = 0.001;
  const Vec3 half(0.3, 0.1, 0.05);
  const Vec3 edge_normal(0.6, 0.0, 0.8);
  struct Placed {
    Vec3 position, normal;
    dem::BoxFace face;
  };
  const Placed placed[] = {
      {Vec3(0.0, 0.0, -half.z() - r + d), -Vec3::UnitZ(), dem::kMinusZ},
      {Vec3(0.1, half.y() + r - d, 0.0), Vec3::UnitY(), dem::kPlusY},
      {Vec3(-half.x() - r + d, 0.0, 0.0), -Vec3::UnitX(), dem::kMinusX},
      {Vec3(half.x(), 0.0, half.z()) + (r - d) * edge_normal, edge_normal, dem::kPlusZ},
  };
  for (const auto& p : placed) {
    dem::SphereSpec s;
    s.position = p.position;
    s.radius = r;
    sim.add_sphere(s);
  }
  dem::RigidBox box;
  box.name = "sleeper";
  box.half_extent = half;
  box.mass = 10.0;
  box.material = 1;
  sim.add_box(box);
  sim.prepare();
  const double kn = 2e6 * 5e9 / (2e6 + 5e9);
  const auto& faces = sim.box_face_forces(0);
  Vec3 sum = Vec3::Zero();
  for (const auto& f : faces) sum += f;
  CHECK((sum - sim.box_force(0)).norm() < 1e-12 * sim.box_force(0).norm() + 1e-12);
  for (const auto& p : placed) {
    CAPTURE(p.face, faces[p.face].transpose());
    CHECK(dem::box_face(p.normal) == p.face);
    CHECK((faces[p.face] + kn * d * p.normal).norm() < 1e-12 * kn * d);
  }
  for (dem::BoxFace empty : {dem::kPlusX, dem::kMinusY}) CHECK(faces[empty].norm() == 0.0);
}
