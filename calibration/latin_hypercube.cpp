#include "calibration/latin_hypercube.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <memory>
#include <numeric>
#include <stdexcept>

namespace mfdem::calibration {

std::vector<std::vector<double>> latin_hypercube(const std::vector<Bounds>& bounds, int samples,
                                                 std::uint64_t seed) {
  if (samples < 1) throw std::invalid_argument("a Latin hypercube needs at least one sample");
  for (const auto& b : bounds)
    if (!(b.upper > b.lower)) throw std::invalid_argument("Latin hypercube bound has upper <= lower");
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(seed));
  std::vector<std::vector<double>> points(samples, std::vector<double>(bounds.size()));
  std::vector<int> slot(samples);
  for (std::size_t axis = 0; axis < bounds.size(); ++axis) {
    std::iota(slot.begin(), slot.end(), 0);
    gsl_ran_shuffle(rng.get(), slot.data(), slot.size(), sizeof(int));
    const double width = (bounds[axis].upper - bounds[axis].lower) / samples;
    for (int s = 0; s < samples; ++s)
      points[s][axis] = bounds[axis].lower + (slot[s] + gsl_rng_uniform(rng.get())) * width;
  }
  return points;
}

}  // namespace mfdem::calibration
