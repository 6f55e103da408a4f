#include "calibration/sobol_design.hpp"

#include <gsl/gsl_qrng.h>
#include <gsl/gsl_rng.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

namespace mfdem::calibration {

namespace {
constexpr std::size_t kSobolMaxDimension = 40;  // gsl_qrng_sobol's limit
}

std::vector<std::vector<double>> sobol_design(const std::vector<Bounds>& bounds, int samples,
                                              std::optional<std::uint64_t> shift_seed) {
  if (samples < 1) throw std::invalid_argument("a Sobol design needs at least one sample");
  if (bounds.empty() || bounds.size() > kSobolMaxDimension)
    throw std::invalid_argument("a Sobol design takes 1 to 40 parameters (got " + std::to_string(bounds.size()) + ")");
  for (const auto& b : bounds)
    if (!(b.upper > b.lower)) throw std::invalid_argument("Sobol design bound has upper <= lower");
  const auto dimension = static_cast<unsigned int>(bounds.size());
  std::unique_ptr<gsl_qrng, decltype(&gsl_qrng_free)> sequence(gsl_qrng_alloc(gsl_qrng_sobol, dimension),
                                                               gsl_qrng_free);
  std::vector<double> shift(bounds.size(), 0.0);
  if (shift_seed) {
    std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
    gsl_rng_set(rng.get(), static_cast<unsigned long>(*shift_seed));
    for (double& s : shift) s = gsl_rng_uniform(rng.get());
  }
  std::vector<std::vector<double>> points(samples, std::vector<double>(bounds.size()));
  std::vector<double> unit(bounds.size());
  for (auto& point : points) {
    gsl_qrng_get(sequence.get(), unit.data());
    for (std::size_t a = 0; a < bounds.size(); ++a) {
      double u = unit[a] + shift[a];
      u -= std::floor(u);
      point[a] = bounds[a].lower + u * (bounds[a].upper - bounds[a].lower);
    }
  }
  return points;
}

}  // namespace mfdem::calibration
