// Head-on impacts against the closed form of the never-tensile linear spring-dashpot
// (tests/physics/linear_dashpot.hpp, Schwager & Poeschel 2007): contact duration, coefficient of
// restitution and, between two spheres, momentum conservation.
//
// Where the tolerances come from (w0 = sqrt(kn/m_eff), dt = time step, here w0 dt = 0.01):
//  - duration: the solver sees the contact only at step times, so its first and last force
//    evaluations are each up to one step late/early: |n_force dt - t_c| <= dt. With a dashpot
//    there is a second, systematic O(dt) term: velocity Verlet evaluates the force after the
//    first half kick, so the dashpot reads the half-step velocity, dt/2 old. To first order the
//    solver integrates (m_eff - cn dt/2) d'' + cn d' + kn d = 0: the mass is low by a fraction
//    beta w0 dt, which raises w0 by beta w0 dt/2 and beta by beta^2 w0 dt/2 and so shortens the
//    contact by up to beta w0 dt t_c (measured 0.4 dt at beta = 0.3, 1.9 dt at beta = 1.5; the
//    same scheme and error as LAMMPS fix nve/sphere with a velocity-dependent pair force).
//    Bound used: dt (1 + beta w0 t_c). The velocity-Verlet phase error, (w0 dt)^2/24 of t_c
//    = 4e-6 t_c here, is below dt/100.
//  - restitution: with a dashpot the force jumps from 0 to cn v0 when the contact is first seen;
//    the integrator applies that jump up to half a step early or late, an impulse error up to
//    cn v0 dt/2, i.e. cn dt/(2 m_eff) = beta w0 dt of e; the stale dashpot velocity raises beta
//    by beta^2 w0 dt/2, another O(beta w0 dt). The spring part of the force is continuous at
//    d = 0 and adds only O((w0 dt)^2) = 1e-4. Bound used: beta w0 dt + 2 (w0 dt)^2.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "tests/physics/linear_dashpot.hpp"
#include "tests/physics/scene_helpers.hpp"

using namespace mfdem;
using namespace mfdem::test;

namespace {

// Chosen so the series stiffness matters: a series(2e7, 6e7) = 1.5e7 N/m contact behaves
// measurably differently from a 2e7 or 6e7 N/m one (durations differ by sqrt(4/3) or more).
constexpr double kSphereKn = 2e7;  // N/m
constexpr double kWallKn = 6e7;    // N/m
constexpr double kOtherKn = 5e7;   // N/m, second sphere material
constexpr double kOmegaDt = 0.01;  // w0 dt: about 300 steps per contact
// Contact starts part-way through a step (3.37 steps after the start), the general case.
constexpr double kApproachSteps = 3.37;

struct Impact {
  double duration = 0.0;  // s, force steps x dt
  double omega0 = 0.0;    // rad/s
  double dt = 0.0;        // s
  double restitution = 0.0;
  double smallest_force = 0.0;  // N, over all steps: never negative (never tensile)
};

double restitution_bound(double beta) { return beta * kOmegaDt + 2.0 * kOmegaDt * kOmegaDt; }

double duration_bound(double beta, double t_c, double dt, double omega0) {
  return dt * (1.0 + beta * omega0 * t_c);
}

// A sphere falls (without gravity) onto a floor of a stiffer material at 1 m/s.
Impact sphere_on_wall(double beta) {
  const SerialThreads serial;
  const double radius = 0.02, v0 = 1.0;
  const auto materials = two_materials(make_material("stone", kSphereKn, kSphereKn, 0.5, beta),
                                       make_material("wall", kWallKn, kWallKn, 0.5, beta));
  const double kn = dem::series_stiffness(kSphereKn, kWallKn);
  const double m_eff = sphere_mass(radius);  // the wall does not move
  Impact result;
  result.omega0 = std::sqrt(kn / m_eff);
  result.dt = kOmegaDt / result.omega0;
  dem::Simulation sim(box_domain(Vec3(-0.1, -0.1, -0.1), Vec3(0.1, 0.1, 0.1)), materials,
                      fixed_step(result.dt));
  const double gap = kApproachSteps * v0 * result.dt;
  sim.add_sphere(sphere(Vec3(0.0, 0.0, radius + gap), radius, 0, Vec3(0.0, 0.0, -v0)));
  sim.add_wall(floor_wall(1));
  sim.prepare();
  int force_steps = 0;
  for (int k = 0; k < 100000; ++k) {
    sim.step();
    const double f = floor_normal_force(sim);
    result.smallest_force = std::min(result.smallest_force, f);
    if (f > 0.0) ++force_steps;
    else if (force_steps > 0) break;  // free flight from here on: the velocity is final
  }
  result.duration = force_steps * result.dt;
  result.restitution = sim.bodies().velocity[0].z() / v0;
  return result;
}

}  // namespace

TEST_CASE("never-tensile linear dashpot: the closed form differs from the textbook one",
          "[physics][impact]") {
  // beta = 0.3: textbook e = exp(-pi beta/sqrt(1-beta^2)) = 0.3723, without tension 0.4510.
  // The gap (0.079) is 25x the restitution tolerance of the simulations below (0.0032), so they
  // can tell the two laws apart.
  CHECK(restitution_with_tension(0.3) == Approx(0.3723).margin(1e-4));
  CHECK(restitution_without_tension(0.3) == Approx(0.4510).margin(1e-4));
  CHECK(restitution_without_tension(0.3) - restitution_with_tension(0.3) >
        20.0 * restitution_bound(0.3));
  // The branches meet at critical damping (e = exp(-2), t_c = 2/w0) from both sides.
  for (double beta : {1.0 - 1e-7, 1.0, 1.0 + 1e-7}) {
    CHECK(restitution_without_tension(beta) == Approx(std::exp(-2.0)).epsilon(1e-5));
    CHECK(contact_duration_without_tension(beta, 1.0) == Approx(2.0).epsilon(1e-5));
  }
  // No damping: a half period and perfect rebound.
  CHECK(restitution_without_tension(0.0) == 1.0);
  CHECK(contact_duration_without_tension(0.0, 2.0) == Approx(std::numbers::pi / 2.0).epsilon(1e-15));
}

TEST_CASE("a sphere hitting a wall rebounds with the never-tensile dashpot restitution",
          "[physics][impact]") {
  // Reference: t_c and e of linear_dashpot.hpp with kn = series(kn_sphere, kn_wall) and
  // m_eff = m; beta >= 1 (overdamped) included, the law allows it through the API.
  for (double beta : {0.0, 0.1, 0.3, 0.7, 1.0, 1.5}) {
    const Impact impact = sphere_on_wall(beta);
    const double t_ref = contact_duration_without_tension(beta, impact.omega0);
    const double e_ref = restitution_without_tension(beta);
    INFO("beta " << beta << ": e " << impact.restitution << " vs " << e_ref << ", t_c "
                 << impact.duration << " vs " << t_ref << " s (dt " << impact.dt << " s)");
    CHECK(impact.smallest_force >= 0.0);
    CHECK(std::abs(impact.duration - t_ref) <= duration_bound(beta, t_ref, impact.dt, impact.omega0));
    CHECK(std::abs(impact.restitution - e_ref) <= restitution_bound(beta));
    if (beta > 0.0 && beta < 1.0) {
      // The textbook value is outside the tolerance: the test tells the two laws apart.
      CHECK(std::abs(impact.restitution - restitution_with_tension(beta)) >
            10.0 * restitution_bound(beta));
    }
  }
}

TEST_CASE("two unequal spheres collide with the closed-form restitution and keep their momentum",
          "[physics][impact]") {
  // Radii 0.02 m and 0.03 m (mass ratio 3.375) of two materials: kn = series(2e7, 5e7) N/m,
  // m_eff = m_a m_b/(m_a + m_b). Momentum: the pair force acts equally and oppositely on both,
  // so total momentum is conserved to round-off (1e-12 of sum |m v|).
  const SerialThreads serial;
  const double ra = 0.02, rb = 0.03, va = 1.5, vb = 0.5;
  const double ma = sphere_mass(ra), mb = sphere_mass(rb);
  const double m_eff = ma * mb / (ma + mb);
  const double kn = dem::series_stiffness(kSphereKn, kOtherKn);
  const double omega0 = std::sqrt(kn / m_eff);
  const double dt = kOmegaDt / omega0;
  for (double beta : {0.0, 0.1, 0.3, 0.7}) {
    const auto materials = two_materials(make_material("small", kSphereKn, kSphereKn, 0.5, beta),
                                         make_material("large", kOtherKn, kOtherKn, 0.5, beta));
    dem::Simulation sim =
        sphere_pair(materials, ra, rb, 1, va, vb, kApproachSteps * (va + vb) * dt, dt);
    sim.prepare();
    REQUIRE(sim.bodies().mass[0] == Approx(ma).epsilon(1e-14));
    REQUIRE(sim.bodies().mass[1] == Approx(mb).epsilon(1e-14));
    const Vec3 p0 = ma * sim.bodies().velocity[0] + mb * sim.bodies().velocity[1];
    const double p_scale = ma * va + mb * vb;
    int force_steps = 0;
    double worst_momentum = 0.0, smallest_force = 0.0;
    for (int k = 0; k < 100000; ++k) {
      sim.step();
      const Vec3 p = ma * sim.bodies().velocity[0] + mb * sim.bodies().velocity[1];
      worst_momentum = std::max(worst_momentum, (p - p0).norm());
      const auto contacts = sim.contacts();
      const double f = contacts.empty() ? 0.0 : contacts[0].force.x();  // on b, along +x
      smallest_force = std::min(smallest_force, f);
      if (f > 0.0) ++force_steps;
      else if (force_steps > 0) break;
    }
    const double e = (sim.bodies().velocity[1].x() - sim.bodies().velocity[0].x()) / (va + vb);
    const double t_ref = contact_duration_without_tension(beta, omega0);
    INFO("beta " << beta << ": e " << e << " vs " << restitution_without_tension(beta)
                 << ", t_c " << force_steps * dt << " vs " << t_ref << " s, momentum error "
                 << worst_momentum / p_scale);
    CHECK(smallest_force >= 0.0);
    CHECK(std::abs(force_steps * dt - t_ref) <= duration_bound(beta, t_ref, dt, omega0));
    CHECK(std::abs(e - restitution_without_tension(beta)) <= restitution_bound(beta));
    CHECK(worst_momentum <= 1e-12 * p_scale);
  }
}
