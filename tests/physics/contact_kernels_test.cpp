// The stateless kernels of dem/contact_law.hpp, driven with prescribed values.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "dem/contact_law.hpp"

using namespace mfdem::dem;

TEST_CASE("the normal force is the spring plus dashpot and never pulls", "[physics][kernels]") {
  // Reference: Fn = max(0, kn d - cn vn), vn > 0 separating. Exact arithmetic: tolerance 0.
  const double kn = 1e7, cn = 500.0;
  int tensile_cases = 0;
  for (double d : {0.0, 1e-7, 1e-5, 1e-4}) {
    for (double vn : {-10.0, -1.0, -1e-3, 0.0, 1e-3, 0.1, 1.0, 10.0}) {
      const double fn = normal_force(kn, cn, d, vn);
      const double unclamped = kn * d - cn * vn;
      CHECK(fn >= 0.0);
      CHECK(fn == (unclamped > 0.0 ? unclamped : 0.0));
      if (unclamped < 0.0) ++tensile_cases;
    }
  }
  CHECK(tensile_cases > 0);  // the clamp was exercised
  // cn = 2 beta sqrt(m_eff kn): beta = 1 is critical damping.
  CHECK(damping_coefficient(1.0, 0.25, 1e6) == Approx(2.0 * 500.0).epsilon(1e-15));
}

TEST_CASE("the slip spring caps at the Coulomb limit and books the slip work",
          "[physics][kernels][friction]") {
  const double k = 1e6, dt = 1e-6, limit = 100.0;
  SECTION("below the limit it is a plain spring and dissipates nothing") {
    Vec3 spring(0.0, -40.0, 0.0);
    const double lost = spring_with_slip(spring, Vec3(0.0, 10.0, 0.0), k, dt, limit);
    CHECK(spring.isApprox(Vec3(0.0, -50.0, 0.0), 1e-15));
    CHECK(lost == 0.0);
  }
  SECTION("steady sliding: the force stays at the limit, the loss is limit x slip") {
    // Already at the limit, pushed on along the same direction: trial |F| = 100 + k v dt = 130,
    // slip (|trial| - limit)/k = 3e-5 m, loss = limit x slip = 3e-3 J (exact up to round-off).
    Vec3 spring(0.0, -limit, 0.0);
    const double lost = spring_with_slip(spring, Vec3(0.0, 30.0, 0.0), k, dt, limit);
    CHECK(spring.norm() == Approx(limit).epsilon(1e-15));
    CHECK(spring.isApprox(Vec3(0.0, -limit, 0.0), 1e-15));
    CHECK(lost == Approx(limit * (130.0 - limit) / k).epsilon(1e-12));
  }
  SECTION("the step that starts sliding books the mean force along the slip times the slip") {
    // From 80 N to a trial of 130 N: 3e-5 m of slip at a force that went from 80 to 100 N. The
    // loss is taken at the mean (80 + 100)/2 = 90 N (trapezoid; the step's force history is
    // unknown, and the mean keeps the account consistent with velocity Verlet, see
    // energy_balance_test.cpp): 2.7e-3 J, not limit x slip = 3e-3 J.
    Vec3 spring(0.0, -80.0, 0.0);
    const double lost = spring_with_slip(spring, Vec3(0.0, 50.0, 0.0), k, dt, limit);
    CHECK(spring.isApprox(Vec3(0.0, -limit, 0.0), 1e-15));
    CHECK(lost == Approx(0.5 * (80.0 + limit) * (130.0 - limit) / k).epsilon(1e-12));
  }
  SECTION("a trial in a new direction is capped along the trial") {
    Vec3 spring(0.0, -limit, 0.0);
    const Vec3 rate(0.0, 0.0, 200.0);  // trial (0, -100, -200)
    const double lost = spring_with_slip(spring, rate, k, dt, limit);
    const Vec3 trial(0.0, -100.0, -200.0);
    CHECK(spring.isApprox(limit * trial.normalized(), 1e-14));
    // Previous force along the slip: 100 x 100/|trial| N.
    const double along = 100.0 * 100.0 / trial.norm();
    CHECK(lost == Approx(0.5 * (limit + along) * (trial.norm() - limit) / k).epsilon(1e-12));
  }
}

TEST_CASE("a load-unload cycle of the tangential spring traces the Coulomb hysteresis loop",
          "[physics][kernels][friction]") {
  // Displacement-controlled cycle u: 0 -> U -> -U -> U under a fixed limit mu Fn = 100 N,
  // ks = 1e6 N/m: F = -ks u up to the slip displacement us = mu Fn/ks = 1e-4 m, then -mu Fn;
  // on reversal the spring unloads with slope ks across 2 us, then slides at +mu Fn.
  // U = 5 us. Dissipated: first loading mu Fn (U - us) = 0.04 J; each closed loop the area of
  // the parallelogram, 2 mu Fn x (2U - 2us) = 0.16 J. Steps of us/10 land on the slip onsets, so
  // every capped step is steady sliding: exact up to round-off (1e-9 relative).
  const double k = 1e6, limit = 100.0, us = limit / k, big_u = 5.0 * us, du = us / 10.0;
  const double dt = 1e-6, speed = du / dt;
  Vec3 spring = Vec3::Zero();
  double lost = 0.0, u = 0.0;
  std::vector<std::pair<double, double>> loop;  // (u, F_x) after each step
  auto move = [&](double to) {
    const double direction = to > u ? 1.0 : -1.0;
    const int steps = static_cast<int>(std::lround(std::abs(to - u) / du));
    for (int s = 0; s < steps; ++s) {
      lost += spring_with_slip(spring, Vec3(direction * speed, 0.0, 0.0), k, dt, limit);
      u += direction * du;
      loop.emplace_back(u, spring.x());
    }
    u = to;
  };
  const auto force_at_step = [&](std::size_t step) { return loop[step - 1].second; };

  move(big_u);
  CHECK(force_at_step(5) == Approx(-0.5 * limit).epsilon(1e-9));  // elastic at us/2
  CHECK(force_at_step(50) == Approx(-limit).epsilon(1e-12));      // sliding at U
  CHECK(lost == Approx(limit * (big_u - us)).epsilon(1e-9));
  const double after_loading = lost;

  move(-big_u);
  CHECK(force_at_step(60) == Approx(0.0).margin(1e-9 * limit));   // unloaded after us back
  CHECK(force_at_step(70) == Approx(limit).epsilon(1e-9));        // reversed after 2 us
  CHECK(force_at_step(150) == Approx(limit).epsilon(1e-12));      // sliding back at -U
  move(big_u);
  CHECK(force_at_step(250) == Approx(-limit).epsilon(1e-12));
  const double per_loop = lost - after_loading;
  CHECK(per_loop == Approx(2.0 * limit * (2.0 * big_u - 2.0 * us)).epsilon(1e-9));
  // Never beyond the limit anywhere on the loop.
  double largest = 0.0;
  for (const auto& step : loop) largest = std::max(largest, std::abs(step.second));
  CHECK(largest <= limit * (1.0 + 1e-15));
}
