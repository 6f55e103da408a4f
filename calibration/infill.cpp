#include "calibration/infill.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "calibration/expected_improvement.hpp"

namespace mfdem::calibration {
namespace {

Evaluation believed(const MisfitSurrogate& s, const Eigen::VectorXd& point, Level level) {
  Evaluation e{point, level, Eigen::VectorXd(static_cast<Eigen::Index>(s.targets().size()))};
  for (std::size_t j = 0; j < s.outputs().size(); ++j) {
    const CoKriging& model = s.outputs()[j];
    e.outputs(static_cast<Eigen::Index>(j)) = level == Level::cheap ? model.predict_cheap(point).mean : model.predict(point).mean;
  }
  return e;
}

}  // namespace

double misfit_expected_improvement(const MisfitSurrogate& surrogate, const Eigen::VectorXd& point) {
  // Called thousands of times per proposal: the outputs are predicted once.
  const std::vector<Prediction> outputs = surrogate.predict_outputs(point);
  const MisfitPrediction p = surrogate.misfit_of(outputs);
  if (surrogate.targets().size() == 1) {  // a single squared error: its exact EI
    const Prediction& y = outputs.front();
    const Target& t = surrogate.targets().front();
    return noise_factor(p.variance, p.noise_variance) * squared_error_expected_improvement(surrogate.incumbent(), y.mean, std::sqrt(y.variance),
                                                             t.value, t.scale);
  }
  return noise_aware_expected_improvement(surrogate.incumbent(), p.mean, p.variance, p.noise_variance);
}

std::vector<Proposal> propose_runs(const MisfitSurrogate& surrogate, std::span<const Evaluation> runs,
                                   const InfillOptions& options) {
  if (options.batch < 1) throw std::invalid_argument("infill: a batch of at least 1 run expected");
  if (surrogate.two_levels() && !(options.cheap_cost > 0.0 && options.cheap_cost < 1.0))
    throw std::invalid_argument("infill: a cheap run's cost must lie between 0 and 1 expensive run");
  MisfitSurrogate current = surrogate;
  std::vector<Evaluation> with_believed(runs.begin(), runs.end());
  std::vector<Proposal> batch;
  for (int k = 0; k < options.batch; ++k) {
    if (k > 0) current.fit(with_believed);
    const BoxOptimum best = maximise_over_box(
        [&](const Eigen::VectorXd& x) { return misfit_expected_improvement(current, x); }, current.bounds(), {},
        options.search);
    Proposal p{best.point, Level::expensive, false, best.value, 1.0};
    if (current.two_levels()) {
      const double cheap = current.variance_share(best.point, Level::cheap) / options.cheap_cost;
      const double expensive = current.variance_share(best.point, Level::expensive) / (1.0 + options.cheap_cost);
      if (cheap > expensive) {
        p.level = Level::cheap, p.cost = options.cheap_cost;
      } else {
        p.with_cheap_twin = true, p.cost = 1.0 + options.cheap_cost;
      }
    }
    batch.push_back(p);
    if (k + 1 == options.batch) break;
    if (p.level == Level::cheap || p.with_cheap_twin) with_believed.push_back(believed(current, p.parameters, Level::cheap));
    if (p.level == Level::expensive) with_believed.push_back(believed(current, p.parameters, Level::expensive));
  }
  return batch;
}

}  // namespace mfdem::calibration
