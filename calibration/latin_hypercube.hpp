#pragma once
// Latin hypercube designs of experiments on a box of parameters (e.g. mu_r x layer height).
// Each of the n samples falls in its own 1/n slice of every axis, so few runs cover the box
// evenly (McKay, Beckman & Conover 1979, Technometrics 21(2), doi:10.2307/1268522).
#include <cstdint>
#include <vector>

namespace mfdem::calibration {

struct Bounds {
  double lower = 0.0;
  double upper = 1.0;
};

// Returns `samples` points, each with one coordinate per bound; seeded, so reproducible.
std::vector<std::vector<double>> latin_hypercube(const std::vector<Bounds>& bounds, int samples,
                                                 std::uint64_t seed);

}  // namespace mfdem::calibration
