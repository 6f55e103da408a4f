#pragma once
// Mass properties of a union of overlapping spheres (a clump), by quasi-Monte Carlo integration.
//
// Pebbles of a clump overlap; counting the overlap twice would make the clump too heavy and its
// inertia wrong. The union is integrated line by line: on a line parallel to x through (y, z),
// each ball cuts a chord; the chords are merged into disjoint intervals, on which the integrals
// of 1, x and x^2 (hence of every entry of x x^T) are exact. What remains is a smooth integral
// over the (y, z) rectangle bounding the clump, done by quasi-Monte Carlo with an unscrambled
// Sobol sequence (GSL gsl_qrng_sobol). Touching or separate spheres need no sampling and are
// exact (the sum of the balls).
//
// Convergence: the first 2^k Sobol points are used for k = min_log2_points, ...; the estimates at
// 2^(k-1) and 2^k points are compared. The result is accepted when two successive comparisons
// agree to within relative_tolerance in volume, centroid (relative to the cube root of the volume)
// and inertia tensor (Frobenius norm); the last difference is reported as the error estimate
// (the tests check it against closed forms).
#include <span>

#include "fidelity/mass_properties.hpp"
#include "fidelity/pebble.hpp"

namespace mfdem::fidelity {

struct UnionIntegrationOptions {
  double relative_tolerance = 1e-5;
  int min_log2_points = 12;
  int max_log2_points = 24;  // 16.8 million points; beyond that the result is marked unconverged
};

struct UnionMassProperties {
  MassProperties properties;
  double volume_error = 0.0;    // estimated relative error of the volume
  double centroid_error = 0.0;  // estimated error of the centroid / volume^(1/3)
  double inertia_error = 0.0;   // estimated relative error of the inertia tensor (Frobenius)
  long long points = 0;         // Sobol points used (0: no overlap, exact)
  bool converged = true;
};

// Throws std::invalid_argument for no pebbles or a radius that is not positive.
UnionMassProperties sphere_union_mass_properties(std::span<const Pebble> pebbles,
                                                 const UnionIntegrationOptions& options = {});

}  // namespace mfdem::fidelity
