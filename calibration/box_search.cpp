#include "calibration/box_search.hpp"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mfdem::calibration {
namespace {

struct Context {
  const std::function<double(const Eigen::VectorXd&)>* f;
  BoxOptimum* best;
};

// Every evaluation is compared with the best so far: a search stopped by round-off or its
// budget loses nothing it has seen.
double evaluate(const std::vector<double>& x, std::vector<double>&, void* data) {
  auto* c = static_cast<Context*>(data);
  const Eigen::VectorXd point = Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
  const double value = (*c->f)(point);
  if (std::isfinite(value) && value > c->best->value) c->best->value = value, c->best->point = point;
  return std::isfinite(value) ? value : -std::numeric_limits<double>::max();
}

}  // namespace

BoxOptimum maximise_over_box(const std::function<double(const Eigen::VectorXd&)>& f, const std::vector<Bounds>& bounds,
                             std::span<const Eigen::VectorXd> extra_starts, const BoxSearch& search) {
  const auto d = static_cast<unsigned>(bounds.size());
  std::vector<double> lower, upper, centre;
  for (const auto& b : bounds) lower.push_back(b.lower), upper.push_back(b.upper), centre.push_back(0.5 * (b.lower + b.upper));
  BoxOptimum best{Eigen::Map<const Eigen::VectorXd>(centre.data(), d), -std::numeric_limits<double>::infinity()};
  Context context{&f, &best};

  nlopt::opt global(nlopt::GN_DIRECT_L, d);
  global.set_lower_bounds(lower);
  global.set_upper_bounds(upper);
  global.set_maxeval(search.global_evaluations > 0 ? search.global_evaluations : 400 * static_cast<int>(d));
  global.set_max_objective(evaluate, &context);
  std::vector<double> x = centre;
  double value = 0.0;
  try {
    global.optimize(x, value);
  } catch (const std::exception&) {
    // Round-off or a flat function: the best point seen is kept in `best`.
  }

  std::vector<Eigen::VectorXd> starts = {best.point};
  for (const auto& s : extra_starts) starts.push_back(s);
  nlopt::opt local(nlopt::LN_BOBYQA, d);
  local.set_lower_bounds(lower);
  local.set_upper_bounds(upper);
  local.set_maxeval(search.local_evaluations);
  local.set_xtol_rel(1e-8);
  local.set_max_objective(evaluate, &context);
  for (const auto& s : starts) {
    std::vector<double> start(s.data(), s.data() + s.size());
    for (unsigned a = 0; a < d; ++a) start[a] = std::clamp(start[a], lower[a], upper[a]);
    try {
      local.optimize(start, value);
    } catch (const std::exception&) {
      // As above.
    }
  }
  return best;
}

}  // namespace mfdem::calibration
