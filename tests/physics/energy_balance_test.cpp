// Energy account of Simulation::energy(): total() = kinetic + gravitational + elastic
// + dissipated - work by walls is conserved, with and without dissipation.
//
// Reference: velocity Verlet conserves, for a linear spring, the shadow energy
//     E~ = 1/2 m v^2 + 1/2 k x^2 (1 - (w dt)^2/4),
// so the true energy at the full steps differs from a conserved quantity by (w dt)^2/4 of the
// energy stored in the springs at that instant (at most the energy available, E_ref), and does
// not drift. The kinks of the force law at contact start and end break the shadow energy a
// little at every collision; that random walk stays far below the bound over the 20,000 steps
// here (measured 2.5e-3 E_ref against the bound 4e-2 E_ref). w is the fastest contact
// frequency: for equal spheres of mass m with pair springs kn and ks, w_n^2 = kn (2/m) and
// w_t^2 = ks (1/m + R^2/I) x 2 = 7 ks/m, so here w = w_t.
// The dissipated energy must be booked consistently with the same integrator: the dashpot and
// slip work are averaged over each step (dem/contact_law.hpp), so the account of a damped,
// frictional run is also second-order (checked on one impact at two step sizes below).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "tests/physics/scene_helpers.hpp"

using namespace mfdem;
using namespace mfdem::test;

namespace {

constexpr double kRadius = 0.02, kBox = 0.2;  // m
constexpr double kStiffness = 2e7;            // kn = ks of the material, N/m
constexpr int kSpheres = 30;

// 30 spheres on a 4 x 4 lattice of pitch 0.05 m in a closed 0.2 m box, seeded random velocities
// up to 2 m/s per component and spins up to 50 rad/s.
dem::Simulation sphere_box(double friction, double damping_ratio, const Vec3& gravity) {
  dem::SimulationSettings settings;  // automatic step: 0.2 of the critical one
  settings.gravity = gravity;
  dem::Simulation sim(box_domain(Vec3::Zero(), Vec3::Constant(kBox)),
                      one_material(make_material("stone", kStiffness, kStiffness, friction, damping_ratio)),
                      settings);
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int s = 0; s < kSpheres; ++s) {
    const Vec3 position(0.025 + 0.05 * (s % 4), 0.025 + 0.05 * (s / 4 % 4), 0.025 + 0.05 * (s / 16));
    const Vec3 velocity = 2.0 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 spin = 50.0 * Vec3(u(rng), u(rng), u(rng));
    sim.add_sphere(sphere(position, kRadius, 0, velocity, spin));
  }
  for (const auto& w : dem::box_walls("box", Vec3::Zero(), Vec3::Constant(kBox), false, 0)) sim.add_wall(w);
  sim.prepare();
  return sim;
}

// Fastest contact frequency times the step (header comment).
double fastest_omega_dt(const dem::Simulation& sim) {
  const double kn = dem::series_stiffness(kStiffness, kStiffness);
  const double m = sphere_mass(kRadius);
  const double w = std::sqrt(std::max(2.0 * kn / m, 7.0 * kn / m));
  return w * sim.time_step();
}

double mechanical(const dem::EnergyReport& e) { return e.kinetic() + e.gravitational + e.elastic; }

}  // namespace

TEST_CASE("without damping or friction the total energy is conserved over many collisions",
          "[physics][energy]") {
  const SerialThreads serial;
  dem::Simulation sim = sphere_box(0.0, 0.0, Vec3::Zero());
  const dem::EnergyReport e0 = sim.energy();
  const double w_dt = fastest_omega_dt(sim);
  const double bound = w_dt * w_dt / 4.0 * e0.kinetic();  // no gravity: E_ref = initial kinetic
  double worst = 0.0;
  int contact_starts = 0;
  dem::Index previous_contacts = sim.active_contact_count();
  for (int k = 1; k <= 20000; ++k) {
    sim.step();
    const dem::Index contacts = sim.active_contact_count();
    contact_starts += std::max(0, contacts - previous_contacts);
    previous_contacts = contacts;
    if (k % 100 == 0) worst = std::max(worst, std::abs(sim.energy().total() - e0.total()));
  }
  const dem::EnergyReport e = sim.energy();
  INFO("w dt " << w_dt << ", " << contact_starts << " contact starts, worst |total - total0| "
               << worst << " J = " << worst / e0.kinetic() << " E_kin0 (bound " << bound << " J)");
  CHECK(contact_starts >= 300);  // many collisions (about 700)
  CHECK(worst <= bound);
  CHECK(e.dissipated() == 0.0);
  // mu = 0: no tangential force, so the spins never change (rotational energy constant).
  CHECK(e.kinetic_rotational == Approx(e0.kinetic_rotational).epsilon(1e-12));
}

TEST_CASE("with damping and friction the mechanical energy never grows and the account balances",
          "[physics][energy]") {
  // beta = 0.3, mu = 0.5, gravity on. Between checks (100 steps) the mechanical energy may rise
  // only by the shadow-energy offset (w dt)^2/4 of the elastic energy then stored (plus 1e-12 of
  // E_ref for round-off); total() stays within (w dt)^2/4 E_ref, E_ref = the initial mechanical
  // energy above the lowest state (every sphere resting on the floor, potential m g R).
  const SerialThreads serial;
  const double g = 9.81;
  dem::Simulation sim = sphere_box(0.5, 0.3, Vec3(0.0, 0.0, -g));
  const dem::EnergyReport e0 = sim.energy();
  const double e_ref = mechanical(e0) - kSpheres * sphere_mass(kRadius) * g * kRadius;
  const double w_dt = fastest_omega_dt(sim);
  const double offset = w_dt * w_dt / 4.0;
  double previous = mechanical(e0), worst_growth = -1e300, worst_total = 0.0;
  for (int k = 1; k <= 20000; ++k) {
    sim.step();
    if (k % 100 != 0) continue;
    const dem::EnergyReport e = sim.energy();
    worst_growth = std::max(worst_growth, mechanical(e) - previous - offset * e.elastic);
    previous = mechanical(e);
    worst_total = std::max(worst_total, std::abs(e.total() - e0.total()));
  }
  const dem::EnergyReport e = sim.energy();
  INFO("w dt " << w_dt << ": largest growth beyond the offset " << worst_growth
               << " J, worst |total - total0| " << worst_total << " J = " << worst_total / e_ref
               << " E_ref (bound " << offset * e_ref << " J); dissipated: damping "
               << e.dissipated_damping << " J, friction " << e.dissipated_friction << " J");
  CHECK(worst_growth <= 1e-12 * e_ref);
  CHECK(worst_total <= offset * e_ref);
  // Most of the energy went where the account says (both channels active).
  CHECK(e.dissipated_damping > 0.2 * e_ref);
  CHECK(e.dissipated_friction > 0.1 * e_ref);
  CHECK(mechanical(e) < 0.2 * e_ref + kSpheres * sphere_mass(kRadius) * g * kRadius);
}

TEST_CASE("the energy account of a damped frictional impact converges at second order",
          "[physics][energy]") {
  // One sphere hits a wall obliquely (vt = 5, vn = 1 m/s) with beta = 0.3 and mu = 0.3: it
  // slides, so both the dashpot and the slip dissipate. After the impact (no spring loaded, no
  // gravity) total() - total0 is the account's error. Velocity Verlet makes it O((w dt)^2):
  // from w dt = 0.08 to 0.01 it must shrink by far more than the factor 8 of a first-order
  // error (expected 64; accepted: more than 20, since where the contact starts and ends within
  // a step scatters single halvings between 3 and 5). Booking each step's loss with the force
  // at its end only, instead of the mean over the step, leaves an O(w dt) error (measured
  // 1.0e-2 and 1.4e-3 of the loss: a factor 7). Bound at each step: (w dt)^2/4 of the loss.
  const SerialThreads serial;
  const double radius = 0.02, vt = 5.0, vn = 1.0, kn = 2e7;
  const auto materials = one_material(make_material("stone", kn, 2.0 / 7.0 * kn, 0.3, 0.3));
  const double w0 = std::sqrt(dem::series_stiffness(kn, kn) / sphere_mass(radius));
  const auto error_at = [&](double w_dt) {
    const double dt = w_dt / w0;
    dem::Simulation sim(box_domain(Vec3(-0.1, -0.1, -0.1), Vec3(0.1, 0.1, 0.1)), materials,
                        fixed_step(dt));
    sim.add_sphere(sphere(Vec3(0.0, 0.0, radius + 3.37 * vn * dt), radius, 0, Vec3(vt, 0.0, -vn)));
    sim.add_wall(floor_wall(0));
    sim.prepare();
    const double total0 = sim.energy().total();
    bool touched = false;
    for (int k = 0; k < 1000000; ++k) {
      sim.step();
      const bool force = floor_normal_force(sim) > 0.0;
      if (touched && !force && sim.bodies().position[0].z() > radius) break;
      touched = touched || force;
    }
    const dem::EnergyReport e = sim.energy();
    return std::pair{std::abs(e.total() - total0) / e.dissipated(), e.dissipated()};
  };
  const auto [coarse, lost_coarse] = error_at(0.08);
  const auto [fine, lost_fine] = error_at(0.01);
  INFO("relative account error " << coarse << " at w dt = 0.08, " << fine << " at 0.01 (ratio "
                                 << coarse / fine << "); dissipated " << lost_coarse << " J");
  CHECK(coarse / fine > 20.0);
  CHECK(coarse <= 0.08 * 0.08 / 4.0);
  CHECK(fine <= 0.01 * 0.01 / 4.0);
}
