#include "fidelity/stone_generator.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "fidelity/convex_hull.hpp"

namespace mfdem::fidelity {

namespace {

constexpr int max_vertices = 1000;
constexpr int max_stretch_iterations = 50;
constexpr double stretch_tolerance = 1e-9;

}  // namespace

void check_stone_spec(const StoneSpec& spec) {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument(fmt::format("stone '{}': {}", spec.name, what));
  };
  if (!(spec.elongation >= 1.0) || !std::isfinite(spec.elongation))
    fail(fmt::format("elongation L/I must be >= 1 (got {})", spec.elongation));
  if (!(spec.flatness > 0.0 && spec.flatness <= 1.0)) fail(fmt::format("flatness S/I must be in (0, 1] (got {})", spec.flatness));
  if (spec.vertices < 8 || spec.vertices > max_vertices)
    fail(fmt::format("vertices must be between 8 and {} (got {})", max_vertices, spec.vertices));
}

TriangleMesh generate_stone(const StoneSpec& spec) {
  check_stone_spec(spec);
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), &gsl_rng_free);
  gsl_rng_set(rng.get(), spec.seed);
  const Vec3 semi_axes(spec.elongation / 2.0, 0.5, spec.flatness / 2.0);
  std::vector<Vec3> points(spec.vertices);
  for (auto& p : points) {
    double x, y, z;
    gsl_ran_dir_3d(rng.get(), &x, &y, &z);
    p = Vec3(x, y, z).cwiseProduct(semi_axes);
  }
  TriangleMesh stone = convex_hull(points);

  // Stretch along the principal axes until the dimensions along them are (L/I, 1, S/I). The axes
  // move a little with each stretch, hence the iteration; it converges in a few steps.
  const std::array<double, 3> target{spec.flatness, 1.0, spec.elongation};  // ascending
  for (int iteration = 0; iteration < max_stretch_iterations; ++iteration) {
    const MassProperties solid = mesh_mass_properties(stone);
    const Mat3 axes = principal_axes(solid.inertia).axes;
    std::array<double, 3> extent{};
    for (int k = 0; k < 3; ++k) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& v : stone.vertices) {
        const double s = (v - solid.centroid).dot(axes.col(k));
        lo = std::min(lo, s), hi = std::max(hi, s);
      }
      extent[k] = hi - lo;
    }
    std::array<int, 3> order{0, 1, 2};  // axes by extent, ascending
    std::sort(order.begin(), order.end(), [&](int a, int b) { return extent[a] < extent[b]; });
    Vec3 stretch;
    double worst = 0.0;
    for (int rank = 0; rank < 3; ++rank) {
      stretch[order[rank]] = target[rank] / extent[order[rank]];
      worst = std::max(worst, std::abs(stretch[order[rank]] - 1.0));
    }
    for (auto& v : stone.vertices) v = axes * stretch.cwiseProduct(axes.transpose() * (v - solid.centroid));
    if (worst < stretch_tolerance) break;
  }
  return stone;
}

}  // namespace mfdem::fidelity
