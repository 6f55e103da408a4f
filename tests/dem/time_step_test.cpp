// The critical time step (dem/time_step.hpp) against the exact stability limit of one contact:
// velocity Verlet on a linear system is stable for dt < 2 / w_max, w_max^2 the largest
// eigenvalue of M^-1/2 K M^-1/2. For the coupled shear and rolling springs of spheres the
// limit must never exceed the exact one (the run would blow up) and should not fall far below it
// (every ball model would pay for it in steps).
#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "tests/dem/builders.hpp"

namespace {

using Catch::Matchers::Contains;
using mfdem::dem::Simulation;
using mfdem::dem::Vec3;
using namespace mfdem::dem_test;

// w_max^2 of the tangential-rotational modes in one plane: DOFs (y, theta) per body, the shear
// spring on the slip y_b - y_a - r_a theta_a - r_b theta_b, the rolling spring (kr = ks Rbar^2)
// on theta_a - theta_b. A body of zero mass is a wall (held).
double exact_shear_rolling(double ks, double m_a, double i_a, double r_a, double m_b, double i_b, double r_b) {
  const bool wall = m_b == 0.0;
  const int n = wall ? 2 : 4;
  Eigen::VectorXd s(n), t(n), inv_sqrt_m(n);
  const double rbar = wall ? r_a : r_a * r_b / (r_a + r_b);
  s.head(2) << -1.0, -r_a;
  t.head(2) << 0.0, 1.0;
  inv_sqrt_m.head(2) << 1.0 / std::sqrt(m_a), 1.0 / std::sqrt(i_a);
  if (!wall) {
    s.tail(2) << 1.0, -r_b;
    t.tail(2) << 0.0, -1.0;
    inv_sqrt_m.tail(2) << 1.0 / std::sqrt(m_b), 1.0 / std::sqrt(i_b);
  }
  const Eigen::VectorXd sp = inv_sqrt_m.cwiseProduct(s), tp = inv_sqrt_m.cwiseProduct(t);
  const Eigen::MatrixXd k = ks * sp * sp.transpose() + ks * rbar * rbar * tp * tp.transpose();
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k).eigenvalues().maxCoeff();
}

}  // namespace

TEST_CASE("critical step of two equal spheres with rolling resistance: within 4 % below the exact limit",
          "[dem][time_step]") {
  constexpr double r = 0.02;
  MaterialParameters p;  // 2e7 N/m per material: ks = 1e7 N/m per contact
  p.rolling_friction = 0.3;
  Simulation sim(box_domain(Vec3::Constant(-1.0), Vec3::Constant(1.0)), material_table({p}), settings(Vec3::Zero()));
  sim.add_sphere({Vec3(0, 0, 0), Vec3::Zero(), Vec3::Zero(), r, 0});
  sim.add_sphere({Vec3(0.5, 0, 0), Vec3::Zero(), Vec3::Zero(), r, 0});
  sim.prepare();
  const double ks = sim.materials().pair(0, 0).shear_stiffness, kn = sim.materials().pair(0, 0).normal_stiffness;
  REQUIRE(ks == 1e7);
  const double m = sphere_mass(r), i = sphere_inertia(r);
  // Equal spheres: the shear mode (7 ks / m) and the rolling mode (1.25 ks / m) do not couple.
  const double w2 = std::max(exact_shear_rolling(ks, m, i, r, m, i, r), 2.0 * kn / m);
  CHECK_THAT(exact_shear_rolling(ks, m, i, r, m, i, r), Catch::Matchers::WithinRel(7.0 * ks / m, 1e-12));
  const double exact = 2.0 / std::sqrt(w2);
  const auto limit = sim.time_step_limit();
  CAPTURE(limit.limit, exact, limit.reason);
  CHECK(limit.limit <= exact * (1.0 + 1e-12));  // never above: that would be unstable
  CHECK(limit.limit >= 0.96 * exact);           // the sum of the modes (8.25 ks / m) gave 0.921
  CHECK_THAT(limit.reason, Contains("coupled shear and rolling springs of ballast-ballast"));
}

TEST_CASE("critical step of graded spheres with rolling resistance: below the exact limit of their worst pair, "
          "at 0.94 of it", "[dem][time_step]") {
  // Radii r and 4 r, as the balls of a graded bed span (the study bed's equal-volume spheres of its
  // 31.5-63 mm stones: 8.9-39 mm). The rolling mode is bounded per ball, Rbar taken with the
  // largest partner: for the small ball Rbar = 0.8 r, B = 3.2 and C = 2 in ks / m_small beside the
  // shear mode A = 7, a limit of 0.944 of the exact one (7, two small spheres). The former bound,
  // the largest radius with the lightest inertia (B 20, C 5), gave 0.568: the balls' step 0.52 of
  // what the safety factor allows on the study bed.
  constexpr double r = 0.01;
  MaterialParameters p;
  p.rolling_friction = 0.3;
  Simulation sim(box_domain(Vec3::Constant(-1.0), Vec3::Constant(1.0)), material_table({p}), settings(Vec3::Zero()));
  sim.add_sphere({Vec3(0, 0, 0), Vec3::Zero(), Vec3::Zero(), r, 0});
  sim.add_sphere({Vec3(0.3, 0, 0), Vec3::Zero(), Vec3::Zero(), r, 0});
  sim.add_sphere({Vec3(-0.4, 0, 0), Vec3::Zero(), Vec3::Zero(), 4.0 * r, 0});
  sim.prepare();
  const double ks = sim.materials().pair(0, 0).shear_stiffness, kn = sim.materials().pair(0, 0).normal_stiffness;
  const double m_s = sphere_mass(r), i_s = sphere_inertia(r), m_l = sphere_mass(4.0 * r), i_l = sphere_inertia(4.0 * r);
  // Every pair the material allows, the large-large one included (the bound cannot know it has one).
  const double w2 = std::max({exact_shear_rolling(ks, m_s, i_s, r, m_s, i_s, r),
                              exact_shear_rolling(ks, m_s, i_s, r, m_l, i_l, 4.0 * r),
                              exact_shear_rolling(ks, m_l, i_l, 4.0 * r, m_l, i_l, 4.0 * r), 2.0 * kn / m_s});
  CHECK_THAT(w2, Catch::Matchers::WithinRel(7.0 * ks / m_s, 1e-12));  // two small spheres: the shear mode
  const double exact = 2.0 / std::sqrt(w2);
  const auto limit = sim.time_step_limit();
  CAPTURE(limit.limit, exact, limit.reason);
  CHECK(limit.limit <= exact * (1.0 + 1e-12));
  CHECK_THAT(limit.limit / exact, Catch::Matchers::WithinAbs(std::sqrt(7.0 / (5.1 + std::sqrt(1.9 * 1.9 + 4.0))), 1e-3));
}

TEST_CASE("critical step of a sphere with rolling resistance on a stiff wall: the exact limit", "[dem][time_step]") {
  constexpr double r = 0.02;
  MaterialParameters p;
  p.rolling_friction = 0.3;
  MaterialParameters wall = p;
  wall.name = "wall";
  wall.stiffness = 1e12;  // the sphere-wall contact (about 2e7 N/m) twice as stiff as sphere-sphere: it sets the step
  Simulation sim(box_domain(Vec3::Constant(-1.0), Vec3::Constant(1.0)), material_table({p, wall}),
                 settings(Vec3::Zero()));
  sim.add_sphere({Vec3(0, 0, 0.5), Vec3::Zero(), Vec3::Zero(), r, 0});
  sim.add_wall(floor_wall(1));
  sim.prepare();
  const double ks = sim.materials().pair(0, 1).shear_stiffness, kn = sim.materials().pair(0, 1).normal_stiffness;
  const double m = sphere_mass(r), i = sphere_inertia(r);
  // One body: the 2 x 2 problem is exact, w^2 = ks (6 + sqrt(26)) / (2 m) for a solid sphere.
  const double w2 = exact_shear_rolling(ks, m, i, r, 0.0, 0.0, 0.0);
  CHECK_THAT(w2, Catch::Matchers::WithinRel(ks * (6.0 + std::sqrt(26.0)) / (2.0 * m), 1e-12));
  REQUIRE(w2 > kn / m);
  const auto limit = sim.time_step_limit();
  CAPTURE(limit.limit, limit.reason);
  CHECK_THAT(limit.limit, Catch::Matchers::WithinRel(2.0 / std::sqrt(w2), 1e-9));
  CHECK_THAT(limit.reason, Contains("on wall 'floor'"));
}

TEST_CASE("a contact type that cannot occur does not limit the step: a lone sphere with no walls",
          "[dem][time_step]") {
  MaterialParameters p;
  p.rolling_friction = 0.3;
  const auto make = [&](int spheres) {
    Simulation sim(box_domain(Vec3::Constant(-1.0), Vec3::Constant(1.0)), material_table({p}),
                   settings(Vec3(0, 0, -kGravity), 1e-3));  // far above any contact's limit (about 1e-5 s)
    for (int k = 0; k < spheres; ++k) sim.add_sphere({Vec3(0.3 * k, 0, 0), Vec3::Zero(), Vec3::Zero(), 0.02, 0});
    return sim;
  };
  Simulation alone = make(1);
  CHECK_NOTHROW(alone.prepare());  // nothing it can touch: the given step stands
  CHECK_FALSE(alone.time_step_limit().contact_possible);
  CHECK(alone.time_step() == 1e-3);
  Simulation pair = make(2);
  CHECK_THROWS_WITH(pair.prepare(), Contains("above the stability limit") && Contains("ballast-ballast"));
}
