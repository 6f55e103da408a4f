#pragma once
// NLopt applied directly to a (noisy) function: the comparison the surrogate loop must beat.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "studies/benchmarks/calibration_functions/test_functions.hpp"

namespace mfdem::benchmarks {

// After each evaluation: its cost so far and the true (noise-free) gap to the minimum of the point
// the method would return then (the best point it has observed).
struct TracePoint {
  double cost = 0.0;
  double gap = 0.0;
};

// The NLopt algorithms compared: BOBYQA, Sbplx, DIRECT-L, ISRES, CRS2.
const std::vector<std::string>& direct_methods();

// Runs `method` on `observe` (the noisy function) for `budget` evaluations from a random start
// (local methods) or NLopt's seeded random numbers (stochastic global methods).
std::vector<TracePoint> direct_search(const std::string& method, const TestFunction& t,
                                      const std::function<double(const Eigen::VectorXd&)>& observe, int budget,
                                      std::uint64_t seed);

}  // namespace mfdem::benchmarks
