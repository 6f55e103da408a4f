#include "fidelity/sphere_union.hpp"

#include <gsl/gsl_qrng.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace mfdem::fidelity {

namespace {

using Qrng = std::unique_ptr<gsl_qrng, decltype(&gsl_qrng_free)>;

}  // namespace

UnionMassProperties sphere_union_mass_properties(std::span<const Pebble> pebbles,
                                                 const UnionIntegrationOptions& options) {
  if (pebbles.empty()) throw std::invalid_argument("a clump needs at least one pebble");
  Moments balls;
  bool overlap = false;
  for (std::size_t i = 0; i < pebbles.size(); ++i) {
    if (!(pebbles[i].radius > 0.0) || !pebbles[i].centre.allFinite())
      throw std::invalid_argument(fmt::format("pebble {} has radius {}; radii must be positive and centres finite",
                                              i, pebbles[i].radius));
    balls += ball_moments(pebbles[i].centre, pebbles[i].radius);
    for (std::size_t j = 0; j < i; ++j)
      overlap |= (pebbles[i].centre - pebbles[j].centre).norm() < pebbles[i].radius + pebbles[j].radius;
  }
  UnionMassProperties result;
  if (!overlap) {  // touching or apart: the sum of the balls is exact
    result.properties = mass_properties(balls);
    return result;
  }

  // Work relative to the centre of the bounding box, for accuracy.
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity()), upper = -lower;
  for (const auto& p : pebbles) {
    lower = lower.cwiseMin(p.centre - Vec3::Constant(p.radius));
    upper = upper.cwiseMax(p.centre + Vec3::Constant(p.radius));
  }
  const Vec3 middle = (lower + upper) / 2.0;
  const double y0 = lower.y() - middle.y(), z0 = lower.z() - middle.z();
  const double height = upper.y() - lower.y(), depth = upper.z() - lower.z();
  std::vector<Pebble> local(pebbles.begin(), pebbles.end());
  for (auto& p : local) p.centre -= middle;

  Qrng sobol(gsl_qrng_alloc(gsl_qrng_sobol, 2), &gsl_qrng_free);
  if (!sobol) throw std::runtime_error("GSL could not allocate a Sobol sequence");

  // Running sums over the lines drawn so far of the line integrals of 1, x and x x^T.
  Moments sum;
  long long drawn = 0;
  std::vector<std::pair<double, double>> chords;
  chords.reserve(local.size());
  auto draw_until = [&](long long target) {
    double u[2];
    for (; drawn < target; ++drawn) {
      gsl_qrng_get(sobol.get(), u);
      const double y = y0 + u[0] * height, z = z0 + u[1] * depth;
      chords.clear();
      for (const auto& p : local) {
        const double rho2 = (y - p.centre.y()) * (y - p.centre.y()) + (z - p.centre.z()) * (z - p.centre.z());
        const double h2 = p.radius * p.radius - rho2;
        if (h2 > 0.0) {
          const double h = std::sqrt(h2);
          chords.emplace_back(p.centre.x() - h, p.centre.x() + h);
        }
      }
      if (chords.empty()) continue;
      std::sort(chords.begin(), chords.end());
      double length = 0.0, x1 = 0.0, x2 = 0.0;  // integrals of 1, x, x^2 along the line's union
      auto add = [&](double a, double b) {
        length += b - a;
        x1 += (b * b - a * a) / 2.0;
        x2 += (b * b * b - a * a * a) / 3.0;
      };
      double a = chords.front().first, b = chords.front().second;
      for (std::size_t k = 1; k < chords.size(); ++k) {
        if (chords[k].first > b) {
          add(a, b);
          a = chords[k].first;
        }
        b = std::max(b, chords[k].second);
      }
      add(a, b);
      sum.volume += length;
      sum.first += Vec3(x1, y * length, z * length);
      Mat3 second;
      second << x2, y * x1, z * x1,
                y * x1, y * y * length, y * z * length,
                z * x1, y * z * length, z * z * length;
      sum.second += second;
    }
  };
  auto estimate = [&]() {
    const double scale = height * depth / static_cast<double>(drawn);
    Moments m;
    m.volume = sum.volume * scale;
    m.first = sum.first * scale;
    m.second = sum.second * scale;
    return mass_properties(m.translated(middle));
  };

  draw_until(1LL << (options.min_log2_points - 1));
  MassProperties previous = estimate();
  int agreements = 0;
  for (int k = options.min_log2_points; k <= options.max_log2_points; ++k) {
    draw_until(1LL << k);
    const MassProperties current = estimate();
    result.properties = current;
    result.points = drawn;
    result.volume_error = std::abs(current.volume - previous.volume) / current.volume;
    result.centroid_error = (current.centroid - previous.centroid).norm() / std::cbrt(current.volume);
    result.inertia_error = relative_tensor_difference(current.inertia, previous.inertia, current.inertia);
    const double worst = std::max({result.volume_error, result.centroid_error, result.inertia_error});
    agreements = worst <= options.relative_tolerance ? agreements + 1 : 0;
    if (agreements == 2) return result;
    previous = current;
  }
  result.converged = false;
  return result;
}

}  // namespace mfdem::fidelity
