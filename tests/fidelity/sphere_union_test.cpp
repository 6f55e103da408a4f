// Mass properties of overlapping pebbles (the union of spheres) against closed forms.
//
// Tolerances: the integration stops when two successive doublings of the Sobol lines agree to
// 1e-5 (UnionIntegrationOptions); the observed errors against the closed forms are 1e-6 to 1e-5,
// so 1e-4 relative leaves a factor of ten. Touching or separate spheres are summed exactly:
// 1e-12.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "fidelity/sphere_union.hpp"
#include "tests/fidelity/sphere_row_exact.hpp"

using namespace mfdem::fidelity;
using mfdem::test::RowSphere;
using mfdem::test::sphere_row_exact;
using std::numbers::pi;

namespace {

constexpr double integration_tolerance = 1e-4;
constexpr double exact_tolerance = 1e-12;

std::vector<Pebble> as_pebbles(const std::vector<RowSphere>& row) {
  std::vector<Pebble> pebbles;
  for (const auto& s : row) pebbles.push_back({Vec3(s.x, 0, 0), s.radius});
  return pebbles;
}

// Relative errors of volume, centroid (per length scale) and inertia tensor (Frobenius).
void require_close(const MassProperties& got, const MassProperties& want, double tolerance) {
  const double scale = std::cbrt(want.volume);
  CHECK(std::abs(got.volume - want.volume) / want.volume < tolerance);
  CHECK((got.centroid - want.centroid).norm() / scale < tolerance);
  CHECK(relative_tensor_difference(got.inertia, want.inertia, want.inertia) < tolerance);
}

}  // namespace

TEST_CASE("one pebble has the mass properties of a ball: V = 4/3 pi R^3, I = 2/5 V R^2", "[fidelity][clump]") {
  const double R = 0.3;
  const Pebble ball{Vec3(1, -2, 0.5), R};
  const auto result = sphere_union_mass_properties(std::span(&ball, 1));
  const double volume = 4.0 / 3.0 * pi * R * R * R;
  CHECK(result.points == 0);
  CHECK(result.properties.volume == Approx(volume).epsilon(exact_tolerance));
  CHECK((result.properties.centroid - ball.centre).norm() < exact_tolerance);
  CHECK(result.properties.inertia(0, 0) == Approx(0.4 * volume * R * R).epsilon(exact_tolerance));
  CHECK(std::abs(result.properties.inertia(0, 1)) < exact_tolerance);
}

TEST_CASE("two equal touching pebbles: the sum of two balls by the parallel axis theorem", "[fidelity][clump]") {
  const double R = 1.0;
  const std::vector<RowSphere> row{{0.0, R}, {2 * R, R}};
  const auto result = sphere_union_mass_properties(as_pebbles(row));
  const double ball = 4.0 / 3.0 * pi * R * R * R;
  CHECK(result.points == 0);  // no overlap: nothing to integrate
  CHECK(result.properties.volume == Approx(2 * ball).epsilon(exact_tolerance));
  CHECK(result.properties.centroid.x() == Approx(R).epsilon(exact_tolerance));
  // Axial: 2 x 2/5 m R^2; transverse: 2 x (2/5 m R^2 + m R^2), each ball at distance R.
  CHECK(result.properties.inertia(0, 0) == Approx(2 * 0.4 * ball * R * R).epsilon(exact_tolerance));
  CHECK(result.properties.inertia(1, 1) == Approx(2 * (0.4 * ball * R * R + ball * R * R)).epsilon(exact_tolerance));
  require_close(result.properties, sphere_row_exact(row), exact_tolerance);
}

TEST_CASE("two equal overlapping pebbles lose the lens V = pi (4R + d)(2R - d)^2 / 12", "[fidelity][clump]") {
  const double R = 0.5;
  for (double d : {0.25 * R, R, 1.5 * R, 1.9 * R}) {
    CAPTURE(d);
    const std::vector<RowSphere> row{{0.1, R}, {0.1 + d, R}};
    const double lens = pi * (4 * R + d) * (2 * R - d) * (2 * R - d) / 12.0;
    const double exact_volume = 2 * 4.0 / 3.0 * pi * R * R * R - lens;
    const MassProperties exact = sphere_row_exact(row);
    REQUIRE(exact.volume == Approx(exact_volume).epsilon(1e-13));  // caps and lens formula agree
    const auto result = sphere_union_mass_properties(as_pebbles(row));
    REQUIRE(result.converged);
    require_close(result.properties, exact, integration_tolerance);
    CHECK(result.volume_error < 1e-5);  // the estimate the template files report
  }
}

TEST_CASE("two unequal overlapping pebbles: radical plane and spherical caps", "[fidelity][clump]") {
  const std::vector<RowSphere> row{{0.0, 1.0}, {1.2, 0.6}};
  const auto result = sphere_union_mass_properties(as_pebbles(row));
  require_close(result.properties, sphere_row_exact(row), integration_tolerance);
}

TEST_CASE("three pebbles in a row, touching and overlapping", "[fidelity][clump]") {
  SECTION("touching: exact sum") {
    const std::vector<RowSphere> row{{0.0, 1.0}, {1.5, 0.5}, {2.5, 0.5}};
    const auto result = sphere_union_mass_properties(as_pebbles(row));
    CHECK(result.points == 0);
    require_close(result.properties, sphere_row_exact(row), exact_tolerance);
  }
  SECTION("overlapping neighbours, unequal radii") {
    const std::vector<RowSphere> row{{0.0, 0.5}, {0.7, 0.4}, {1.3, 0.45}};
    const auto result = sphere_union_mass_properties(as_pebbles(row));
    require_close(result.properties, sphere_row_exact(row), integration_tolerance);
  }
}

TEST_CASE("a turned clump has the same principal moments and the turned centroid", "[fidelity][clump]") {
  // The same union integrated in two frames: lines along x cut the turned clump obliquely.
  const std::vector<RowSphere> row{{0.0, 0.5}, {0.7, 0.4}, {1.3, 0.45}};
  const auto straight = sphere_union_mass_properties(as_pebbles(row));
  const Mat3 turn = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<Pebble> turned = as_pebbles(row);
  for (auto& p : turned) p.centre = turn * p.centre + Vec3(0.2, -0.1, 0.3);
  const auto result = sphere_union_mass_properties(turned);
  CHECK(std::abs(result.properties.volume - straight.properties.volume) / straight.properties.volume < integration_tolerance);
  CHECK((result.properties.centroid - (turn * straight.properties.centroid + Vec3(0.2, -0.1, 0.3))).norm() < integration_tolerance);
  const Vec3 a = principal_axes(result.properties.inertia).moments;
  const Vec3 b = principal_axes(straight.properties.inertia).moments;
  CHECK((a - b).norm() / b.norm() < integration_tolerance);
}

TEST_CASE("a pebble inside another adds nothing", "[fidelity][clump]") {
  const std::vector<Pebble> pebbles{{Vec3::Zero(), 1.0}, {Vec3(0.2, 0.1, 0), 0.5}};
  const auto result = sphere_union_mass_properties(pebbles);
  CHECK(result.properties.volume == Approx(4.0 / 3.0 * pi).epsilon(integration_tolerance));
  CHECK(result.properties.centroid.norm() < integration_tolerance);
}

TEST_CASE("a pebble without a positive radius is refused", "[fidelity][clump]") {
  const std::vector<Pebble> pebbles{{Vec3::Zero(), 1.0}, {Vec3(1, 0, 0), 0.0}};
  CHECK_THROWS_WITH(sphere_union_mass_properties(pebbles), Catch::Contains("pebble 1 has radius 0"));
  CHECK_THROWS_WITH(sphere_union_mass_properties(std::vector<Pebble>{}), Catch::Contains("at least one pebble"));
}
