#include "fidelity/clump_template.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

namespace mfdem::fidelity {

double ClumpTemplate::equivalent_radius(double size) const {
  return size * std::cbrt(3.0 * volume / (4.0 * std::numbers::pi));
}

std::vector<Pebble> ClumpTemplate::pebbles_at(double size) const {
  std::vector<Pebble> scaled = pebbles;
  for (auto& p : scaled) p.centre *= size, p.radius *= size;
  return scaled;
}

Vec3 ClumpTemplate::to_body(const Vec3& x_input) const {
  return input_to_principal * (x_input - centre_of_mass_input) / input_size;
}

ClumpTemplate clump_from_pebbles(std::string name, std::span<const Pebble> input_pebbles, double input_size,
                                 const UnionIntegrationOptions& integration) {
  if (!(input_size > 0.0) || !std::isfinite(input_size))
    throw std::invalid_argument(fmt::format("clump '{}': the stone's size must be positive (got {})", name, input_size));
  // Integrate at unit size so that the tolerances mean the same for every input unit.
  std::vector<Pebble> unit(input_pebbles.begin(), input_pebbles.end());
  for (auto& p : unit) p.centre /= input_size, p.radius /= input_size;
  const UnionMassProperties union_properties = sphere_union_mass_properties(unit, integration);
  if (!union_properties.converged)
    throw std::invalid_argument(fmt::format(
        "clump '{}': the mass properties did not converge to a relative {:g} within {} points (last change {:.2g})",
        name, integration.relative_tolerance, union_properties.points,
        std::max(union_properties.volume_error, union_properties.inertia_error)));
  const MassProperties& p = union_properties.properties;
  const PrincipalAxes principal = principal_axes(p.inertia);

  ClumpTemplate clump;
  clump.name = std::move(name);
  clump.volume = p.volume;
  clump.principal_inertia = principal.moments;
  clump.input_size = input_size;
  clump.centre_of_mass_input = p.centroid * input_size;
  clump.input_to_principal = Quat(Mat3(principal.axes.transpose())).normalized();
  clump.integration = union_properties;
  for (const auto& pebble : unit)
    clump.pebbles.push_back({principal.axes.transpose() * (pebble.centre - p.centroid), pebble.radius});
  return clump;
}

double radius_factor_for_volume(std::span<const Pebble> pebbles, double volume, double tolerance) {
  constexpr int max_iterations = 50;
  // A fixed set of 2^18 Sobol lines makes V(f) a smooth, deterministic function for the secant;
  // its own error (about 1e-5 relative) adds to `tolerance`.
  UnionIntegrationOptions integration;
  integration.relative_tolerance = std::numeric_limits<double>::infinity();
  integration.min_log2_points = 17;
  std::vector<Pebble> scaled(pebbles.begin(), pebbles.end());
  // g(s) = log V(e^s) - log volume, zero at the factor sought; V grows like f^2 to f^3.
  auto g = [&](double s) {
    for (std::size_t i = 0; i < scaled.size(); ++i) scaled[i].radius = pebbles[i].radius * std::exp(s);
    return std::log(sphere_union_mass_properties(scaled, integration).properties.volume / volume);
  };
  double s0 = 0.0, g0 = g(s0);
  double s1 = -g0 / 3.0;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    const double g1 = g(s1);
    if (std::abs(g1) <= tolerance) return std::exp(s1);
    const double s2 = g1 == g0 ? s1 - g1 / 3.0 : s1 - g1 * (s1 - s0) / (g1 - g0);
    s0 = s1, g0 = g1, s1 = s2;
  }
  throw std::runtime_error(fmt::format("no radius factor gives the clump a volume of {} (secant did not converge)", volume));
}

void fit_to_surface(ClumpTemplate& clump, const TriangleMesh& input_surface) {
  SurfaceFit fit;
  fit.surface = input_surface;
  for (auto& v : fit.surface.vertices) v = clump.to_body(v);
  const MassProperties solid = mesh_mass_properties(fit.surface);
  fit.volume = solid.volume;
  fit.centroid = solid.centroid;
  fit.inertia = solid.inertia;
  fit.indices = shape_indices(fit.surface);
  fit.volume_error = (clump.volume - fit.volume) / fit.volume;
  const Mat3 clump_inertia = clump.principal_inertia.asDiagonal();
  fit.inertia_error = relative_tensor_difference(clump_inertia, fit.inertia, fit.inertia);
  for (const auto& pebble : clump.pebbles) {
    const double depth = distance_to_surface(fit.surface, pebble.centre);
    const double reach = inside(fit.surface, pebble.centre) ? pebble.radius - depth : pebble.radius + depth;
    fit.protrusion = std::max(fit.protrusion, reach);
  }
  clump.fit = std::move(fit);
}

}  // namespace mfdem::fidelity
