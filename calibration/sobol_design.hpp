#pragma once
// Quasi-random Sobol designs on a box of parameters (GSL's gsl_qrng_sobol, Bratley & Fox 1988,
// ACM TOMS 14(1):88-100, up to 40 dimensions), optionally shifted: each point moved by one
// uniform random vector modulo 1 in the unit box (a Cranley-Patterson rotation, 1976), seeded, so
// that two campaigns draw different but equally even designs.
#include <cstdint>
#include <optional>
#include <vector>

#include "calibration/latin_hypercube.hpp"

namespace mfdem::calibration {

// `samples` points in the box, one coordinate per bound: the first points of the Sobol sequence
// (GSL's, starting at its first point, the origin) scaled to the box, shifted when
// `shift_seed` is given. Throws std::invalid_argument for no sample, no axis, more than 40 axes
// or a bound with upper <= lower.
std::vector<std::vector<double>> sobol_design(const std::vector<Bounds>& bounds, int samples,
                                              std::optional<std::uint64_t> shift_seed = std::nullopt);

}  // namespace mfdem::calibration
