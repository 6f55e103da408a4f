// Objectivity of the tangential spring: a loaded contact turned rigidly keeps its force and the
// force turns with it (MercuryDPM-style prescribed motion, dem::evaluate_contact called directly).
//
// Rigid motion of the pair with angular velocity W: both contact points move together, so the
// relative velocity and spin at the contact are zero, the normal turns as dn/dt = W x n, and
// the solver turns the spring by dropping its component along the new normal (a tilt, exact
// when W is normal to both n and the force) and by the spin about the normal, W.n
// (frame_spin), applied as t += (W.n dt) n x t and rescaled.
// Tolerances, after a total turn theta = 1 rad in steps of W dt = 1e-3:
//  - magnitude: kept by construction (rescaling): 1e-9 relative covers the round-off of 1000
//    steps (measured 3e-14).
//  - direction, W normal to n and to the force: the tilt is exact; round-off only (1e-12).
//  - direction, W along n: each step turns by atan(W dt) instead of W dt, an error of
//    (W dt)^3/3 per step, theta (W dt)^2/3 = 3.3e-7 rad in all.
//  - direction, W oblique to n: splitting each step's rotation into a tilt of the normal and a
//    turn about the new normal is exact only to first order, so the error grows like
//    theta W dt (measured 0.21 theta W dt = 2.1e-4 rad); bound theta W dt = 1e-3 rad.
// (The same check through a Simulation needs a pair that turns rigidly while pressed together;
// a repulsive contact cannot supply the centripetal force, so the pair would fly apart.)
#include <catch2/catch.hpp>

#include <cmath>

#include "dem/contact_law.hpp"

using namespace mfdem::dem;

namespace {

struct TurnResult {
  double magnitude_error = 0.0;  // | |F| / |F0| - 1 |, worst over the turn
  double angle_error = 0.0;      // rad, between the force and the rigidly turned initial force
  double normal_leak = 0.0;      // |F.n| / |F|, worst over the turn
  double normal_force_error = 0.0;  // |Fn / (kn d) - 1|, worst
};

TurnResult load_then_turn(const Vec3& axis, double omega_dt, double angle) {
  PairParameters p;
  p.normal_stiffness = 1e7;  // N/m
  p.shear_stiffness = 1e7;
  p.friction = 0.5;
  const double dt = 1e-6;  // s
  ContactGeometry g;
  g.overlap = 1e-4;  // Fn = 1000 N, Coulomb limit 500 N
  g.normal = Vec3::UnitX();
  g.damping = damping_coefficient(p.damping_ratio, 0.05, p.normal_stiffness);
  g.rolling_radius = 0.01;
  ContactHistory history;
  // Load: 10 steps of 3 m/s along y give Fs = -ks 3e-5 m ey = -300 N ey, below the limit.
  g.relative_velocity = Vec3(0.0, 3.0, 0.0);
  for (int k = 0; k < 10; ++k) evaluate_contact(p, g, history, dt);
  const Vec3 f0 = history.shear_force;
  REQUIRE(f0.norm() == Approx(300.0).epsilon(1e-9));

  const double omega = omega_dt / dt;
  const int steps = static_cast<int>(std::lround(angle / omega_dt));
  TurnResult r;
  g.relative_velocity = Vec3::Zero();
  for (int k = 1; k <= steps; ++k) {
    const Eigen::AngleAxisd turn(omega * k * dt, axis);
    g.normal = turn * Vec3::UnitX();
    g.frame_spin = omega * axis.dot(g.normal);
    const ContactOutcome out = evaluate_contact(p, g, history, dt);
    const Vec3& f = history.shear_force;
    const Vec3 want = turn * f0;
    r.magnitude_error = std::max(r.magnitude_error, std::abs(f.norm() / f0.norm() - 1.0));
    r.angle_error = std::max(r.angle_error, std::atan2(want.cross(f).norm(), want.dot(f)));
    r.normal_leak = std::max(r.normal_leak, std::abs(f.dot(g.normal)) / f.norm());
    r.normal_force_error =
        std::max(r.normal_force_error, std::abs(out.normal_force / (p.normal_stiffness * g.overlap) - 1.0));
  }
  return r;
}

}  // namespace

TEST_CASE("a loaded contact turned rigidly keeps its tangential force, which turns with it",
          "[physics][objectivity]") {
  constexpr double kOmegaDt = 1e-3, kAngle = 1.0;
  struct Case {
    const char* name;
    Vec3 axis;
    double angle_bound;
  };
  // n0 = x, F0 along -y.
  for (const Case& c : {Case{"about z: normal and force turn in their plane", Vec3::UnitZ(), 1e-12},
                        Case{"about y: along the force", Vec3::UnitY(), 1e-12},
                        Case{"about x: spin about the normal", Vec3::UnitX(),
                             kAngle * kOmegaDt * kOmegaDt / 3.0 * 1.01},
                        Case{"oblique axis (1, 2, 3)", Vec3(1.0, 2.0, 3.0).normalized(),
                             kAngle * kOmegaDt}}) {
    const TurnResult r = load_then_turn(c.axis, kOmegaDt, kAngle);
    INFO(c.name << ": magnitude error " << r.magnitude_error << ", angle error " << r.angle_error
                << " rad (bound " << c.angle_bound << "), normal component " << r.normal_leak);
    CHECK(r.magnitude_error <= 1e-9);
    CHECK(r.angle_error <= c.angle_bound);
    CHECK(r.normal_leak <= 1e-12);
    CHECK(r.normal_force_error <= 1e-12);
  }
}
