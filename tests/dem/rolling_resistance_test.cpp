// Rolling resistance (elastic-plastic spring, Ai et al. 2011 type C): a sphere on a floor wall.
//
// Conventions of the solver (dem/contact_law.hpp, dem/simulation_gather.cpp) used in the derivations:
// the floor is z = 0 with normal +z; the contact point is at -Rc e_z from the centre, with the
// lever Rc = R - d/2 (d = overlap); a sphere moving along +x rolls without slip when its spin
// about +y is w_y = v_x / R, since the contact point moves at v_x - Rc w_y. The shear force on
// the sphere is Ft e_x, giving the torque (-Rc e_z) x (Ft e_x) = -Rc Ft e_y; the rolling moment
// Mr_y opposes w_y and is capped at mu_r R Fn (Rbar = R against a wall), kr = ks R^2.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <vector>

#include "tests/dem/builders.hpp"

namespace {

using mfdem::dem::Simulation;
using mfdem::dem::Vec3;
using namespace mfdem::dem_test;

constexpr double kRadius = 0.05;            // m
constexpr double kMaterialStiffness = 2e7;  // N/m per material; one material for sphere and floor
constexpr double kContactStiffness = 0.5 * kMaterialStiffness;  // series mixing: kn = ks = 1e7 N/m

// One sphere resting on the floor at its static overlap d = Fn / kn under `gravity`, with the
// given velocity and spin; mu large enough that the contact sticks.
Simulation sphere_on_floor(const Vec3& gravity, double friction, double rolling_friction,
                           const Vec3& velocity, const Vec3& spin, double time_step = 0.0) {
  MaterialParameters p;
  p.stiffness = kMaterialStiffness;
  p.friction = friction;
  p.rolling_friction = rolling_friction;
  Simulation sim(box_domain(Vec3(-1.0, -0.5, -0.1), Vec3(2.0, 0.5, 0.5)), material_table({p}),
                 settings(gravity, time_step));
  const double normal_force = sphere_mass(kRadius) * -gravity.z();
  sim.add_sphere(sphere(Vec3(0, 0, kRadius - normal_force / kContactStiffness), kRadius, 0,
                        velocity, spin));
  sim.add_wall(floor_wall(0));
  sim.prepare();
  return sim;
}

// Least-squares slope of y(t).
double fitted_slope(const std::vector<double>& t, const std::vector<double>& y) {
  const double n = static_cast<double>(t.size());
  double st = 0, sy = 0, stt = 0, sty = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    st += t[k], sy += y[k], stt += t[k] * t[k], sty += t[k] * y[k];
  }
  return (n * sty - st * sy) / (n * stt - st * st);
}

}  // namespace

// A sphere rolling on a plane with rolling resistance stops after v0^2 / (2 * 5/7 * mu_r * g).
// Derivation (rolling without slip, a = dv/dt = R dw/dt, moment saturated at Mr = -mu_r R m g):
//   m a = Ft,  I a / R = -R Ft - mu_r R m g,  I = (2/5) m R^2
//   => (2/5) m a = -Ft - mu_r m g = -m a - mu_r m g  =>  a = -(5/7) mu_r g,
// and the distance to stop is v0^2 / (2 |a|). Equivalently, the kinetic energy (7/10) m v0^2 is
// spent by the moment mu_r R m g over the rotation distance / R.
// First-order correction, significant at the tolerance below: the sphere sits in the floor by
// d = m g / kn and the solver puts the contact point at the lever Rc = R - d/2, so rolling
// without slip turns it by distance / Rc, while the moment cap keeps Rbar = R. The energy
// balance then gives distance = (Rc / R) v0^2 / (2 * 5/7 * mu_r * g): 1.4e-5 shorter here
// (2.6e-6 m), and that is what the solver gives.
TEST_CASE("a sphere rolling on a plane stops after v0^2 / (2 * 5/7 * mu_r * g)", "[dem][rolling]") {
  const double mu_r = 0.1, v0 = 0.5;  // |a| = 0.70 m/s^2: stops after 0.18 m in 0.71 s
  Simulation sim = sphere_on_floor(Vec3(0, 0, -kGravity), 1.0, mu_r, Vec3(v0, 0, 0),
                                   Vec3(0, v0 / kRadius, 0));
  const double fn = sphere_mass(kRadius) * kGravity;
  const double lever = kRadius - 0.5 * fn / kContactStiffness;
  const double deceleration = 5.0 / 7.0 * mu_r * kGravity;
  const double textbook = v0 * v0 / (2.0 * deceleration);
  const double expected = lever / kRadius * textbook;
  const double x0 = sim.bodies().position[0].x();
  const double dt = sim.time_step();
  const auto max_steps = static_cast<long long>(2.0 * v0 / deceleration / dt);
  while (sim.bodies().velocity[0].x() > 0.0 && sim.step_count() < max_steps) sim.step();
  REQUIRE(sim.bodies().velocity[0].x() <= 0.0);
  const double distance = sim.bodies().position[0].x() - x0;
  // Tolerance: the springs load elastically before the moment saturates and unload after the
  // stop; each stretch is at most mu_r Fn / ks (rolling: R * mu_r R Fn / kr = mu_r Fn / ks) =
  // 1.4e-7 m here; the stop is found to within one step, |a| dt^2 (2e-9 m at dt = 5.8e-5 s).
  // Twice their sum: 5.8e-7 m, 3e-6 of the distance.
  const double tolerance = 2.0 * (2.0 * mu_r * fn / kContactStiffness + deceleration * dt * dt);
  CAPTURE(textbook, expected, distance, tolerance, dt);
  CHECK(std::abs(distance - expected) <= tolerance);
  // The textbook formula, within the lever correction plus the same tolerance.
  CHECK(std::abs(distance - textbook) <= (textbook - expected) + tolerance);

  // Having stopped, it stays: the saturated springs unload elastically (each stretch
  // <= mu_r Fn / ks, undamped swing twice that) and never reach the cap again.
  const double x_stop = sim.bodies().position[0].x();
  double largest_excursion = 0.0;
  for (int k = 0; k < static_cast<int>(0.3 / dt); ++k) {
    sim.step();
    largest_excursion = std::max(largest_excursion, std::abs(sim.bodies().position[0].x() - x_stop));
  }
  const double rest_bound = 4.0 * mu_r * fn / kContactStiffness;
  CAPTURE(largest_excursion, rest_bound);
  CHECK(largest_excursion <= rest_bound);
}

// On an incline of angle th (gravity tilted: g (sin th, 0, -cos th)) the sphere needs the
// moment R m g sin th to stay at rest (torque of the friction force that holds it); the cap is
// mu_r R m g cos th, so it rests when tan th < mu_r. Above, rolling without slip with the moment
// saturated gives (same algebra as on the plane, plus the slope force m g sin th):
//   a = (5/7) g (sin th - mu_r cos th).
TEST_CASE("a sphere on an incline rests below tan(theta) = mu_r and rolls at (5/7) g (sin - mu_r cos) above",
          "[dem][rolling]") {
  const double mu_r = 0.1;
  const double m = sphere_mass(kRadius);

  SECTION("at rest below the angle of rolling resistance") {
    // At rest the shear spring holds m g sin th (stretch m g sin th / ks) and the rolling spring
    // R m g sin th (rotation R m g sin th / kr, centre displacement R^2 m g sin th / kr =
    // m g sin th / ks): the centre sits 2 m g sin th / ks downhill. Starting from unloaded
    // springs with no damping it swings to twice that: bound 4 m g sin th / ks, with the
    // spring never reaching the cap while tan th < mu_r / 2. Between mu_r / 2 and mu_r the
    // first swing saturates the spring and creeps: a one-degree-of-freedom estimate of the
    // overshoot then gives at most 5.5 static displacements; bound 20 m g sin th / ks.
    const double ratio = GENERATE(0.4, 0.9);
    const double theta = std::atan(ratio * mu_r);
    Simulation sim = sphere_on_floor(kGravity * Vec3(std::sin(theta), 0, -std::cos(theta)), 1.0,
                                     mu_r, Vec3::Zero(), Vec3::Zero());
    const double x0 = sim.bodies().position[0].x();
    double largest = 0.0;
    while (sim.time() < 0.5) {
      sim.step();
      largest = std::max(largest, std::abs(sim.bodies().position[0].x() - x0));
    }
    const double bound = (ratio < 0.5 ? 4.04 : 20.0) * m * kGravity * std::sin(theta) /
                         kContactStiffness;
    // For scale: at tan th = 1.1 mu_r it would have rolled (5/7) g (sin - mu_r cos) t^2 / 2,
    // about 4e-3 m, in the same 0.5 s.
    CAPTURE(ratio, largest, bound);
    CHECK(largest <= bound);
  }

  SECTION("rolling above the angle of rolling resistance") {
    const double theta = std::atan(2.0 * mu_r);
    Simulation sim = sphere_on_floor(kGravity * Vec3(std::sin(theta), 0, -std::cos(theta)), 1.0,
                                     mu_r, Vec3::Zero(), Vec3::Zero());
    const double expected = 5.0 / 7.0 * kGravity * (std::sin(theta) - mu_r * std::cos(theta));
    std::vector<double> t, v;
    double largest_slip = 0.0;
    while (sim.time() < 0.5) {
      sim.step();
      if (sim.time() < 0.05) continue;  // past the start, where the springs load
      t.push_back(sim.time());
      v.push_back(sim.bodies().velocity[0].x());
      largest_slip = std::max(largest_slip, std::abs(sim.bodies().velocity[0].x() -
                                                     kRadius * sim.bodies().angular_velocity[0].y()));
    }
    const double measured = fitted_slope(t, v);
    // Tolerance: the springs start unloaded and, undamped, ring at about 1 kHz around their
    // loaded state with a velocity amplitude ~ Ft / sqrt(ks m) ~ 1e-4 m/s; a least-squares
    // slope over 0.45 s averages it to ~1e-5 of the acceleration. Bound 1e-3 relative.
    CAPTURE(expected, measured, largest_slip);
    CHECK(std::abs(measured - expected) <= 1e-3 * expected);
    // Rolls without sliding (mu = 1 needs only (2/7) tan th + (5/7) mu_r = 0.13): the contact
    // point only moves with the elastic ringing of the shear spring, |v - R w| << v (0.5 m/s).
    CHECK(largest_slip <= 1e-3);
  }
}

// Small rocking on the springs. With x the horizontal displacement of the centre and th the
// rotation about +y, the contact point slips by s = x - Rc th, so
//   shear force on the sphere    Fx = -ks (x - Rc th)
//   its torque about +y          -Rc Fx = ks Rc (x - Rc th)
//   rolling moment               -kr th,  kr = ks R^2
// and the motion obeys M q'' = -K q with q = (x, th), M = diag(m, I),
//   K = [[ks, -ks Rc], [-ks Rc, ks Rc^2 + kr]].
// For a solid sphere (Rc ~ R) the eigenvalues of M^-1 K are (3 +- sqrt(6.5)) ks / m:
// w_high = sqrt(5.55 ks/m), w_low = sqrt(0.45 ks/m). The normal force m g keeps both springs
// far below their caps (tiny amplitude, mu = 1, mu_r = 0.5).
TEST_CASE("a sphere rocking on its shear and rolling springs oscillates at the eigenfrequencies of the 2x2 system",
          "[dem][rolling]") {
  const double m = sphere_mass(kRadius), inertia = sphere_inertia(kRadius);
  const double ks = kContactStiffness, kr = ks * kRadius * kRadius;
  const double overlap = m * kGravity / kContactStiffness;
  const double rc = kRadius - 0.5 * overlap;
  Eigen::Matrix2d stiffness, mass;
  stiffness << ks, -ks * rc, -ks * rc, ks * rc * rc + kr;
  mass << m, 0, 0, inertia;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> modes(stiffness, mass);
  const double w_low = std::sqrt(modes.eigenvalues()[0]);
  const double w_high = std::sqrt(modes.eigenvalues()[1]);
  // A step of 0.05 / w_high: Verlet's frequency error (w dt)^2 / 24 is then 1e-4 at most.
  const double dt = 0.05 / w_high;

  // Counts sign changes of the spin over `periods` periods of w; returns the measured angular
  // frequency from the first and last crossing (crossing times interpolated linearly).
  auto measured_frequency = [&](Simulation& sim, double w, int periods) {
    std::vector<double> crossings;
    double previous = sim.bodies().angular_velocity[0].y();
    double t_previous = sim.time();
    while (sim.time() < periods * 2.0 * std::numbers::pi / w) {
      sim.step();
      const double now = sim.bodies().angular_velocity[0].y();
      if ((previous < 0) != (now < 0))
        crossings.push_back(t_previous + (sim.time() - t_previous) * previous / (previous - now));
      previous = now, t_previous = sim.time();
    }
    REQUIRE(crossings.size() >= 2);
    const double half_periods = static_cast<double>(crossings.size() - 1);
    return std::numbers::pi * half_periods / (crossings.back() - crossings.front());
  };

  SECTION("a tiny spin excites mostly the high mode") {
    // Initial velocity (0, w0) in (x', th') splits into the two modes; the high mode carries
    // about 89 % of the spin amplitude, so the spin crosses zero at the high frequency. The low
    // mode (11 %) shifts a crossing by at most asin(0.12) / w_high; at both ends of 60 periods
    // (119 half periods between the first and last crossing) that is 2 x 0.12 / (119 pi) =
    // 6.5e-4 of the frequency, plus Verlet's (w dt)^2 / 24 = 1e-4. Tolerance 2e-3.
    const double spin = 1e-3;  // rad/s: moment ~1e-8 N m, cap mu_r R m g = 0.36 N m
    Simulation sim = sphere_on_floor(Vec3(0, 0, -kGravity), 1.0, 0.5, Vec3::Zero(),
                                     Vec3(0, spin, 0), dt);
    const double w = measured_frequency(sim, w_high, 60);
    CAPTURE(w, w_high, w_low);
    CHECK(std::abs(w - w_high) <= 2e-3 * w_high);
  }

  SECTION("each mode alone, excited along its eigenvector") {
    const int mode = GENERATE(0, 1);
    const Eigen::Vector2d shape = modes.eigenvectors().col(mode);
    const double w_expected = mode == 0 ? w_low : w_high;
    // 10 nm amplitude of x: the shear force then stays below 0.6 N, far below mu Fn = 14 N.
    const double scale = 1e-8 / std::abs(shape[0]) * w_expected;
    Simulation sim = sphere_on_floor(Vec3(0, 0, -kGravity), 1.0, 0.5, Vec3(scale * shape[0], 0, 0),
                                     Vec3(0, scale * shape[1], 0), dt);
    const double w = measured_frequency(sim, w_expected, 30);
    // Tolerance: Verlet's (w dt)^2 / 24 <= 1e-4 plus the crossing interpolation; 1e-3.
    CAPTURE(mode, w, w_expected);
    CHECK(std::abs(w - w_expected) <= 1e-3 * w_expected);
  }
}
