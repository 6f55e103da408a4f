#include "calibration/misfit_surrogate.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "calibration/box_search.hpp"

namespace mfdem::calibration {

MisfitSurrogate::MisfitSurrogate(std::vector<Bounds> bounds, std::vector<Target> targets, KernelKind kind,
                                 HyperparameterSearch search)
    : bounds_(std::move(bounds)), targets_(std::move(targets)), kind_(kind), search_(search) {
  if (targets_.empty()) throw std::invalid_argument("a calibration needs at least one target");
  for (const auto& t : targets_)
    if (!(t.scale > 0.0) || !std::isfinite(t.value))
      throw std::invalid_argument("a calibration target needs a finite value and a scale > 0");
}

void MisfitSurrogate::fit(std::span<const Evaluation> runs) {
  const auto d = static_cast<Eigen::Index>(bounds_.size());
  const auto m = static_cast<Eigen::Index>(targets_.size());
  Eigen::Index cheap_count = 0, expensive_count = 0;
  for (const auto& r : runs) {
    if (r.parameters.size() != d || r.outputs.size() != m || !r.outputs.allFinite() || !r.parameters.allFinite())
      throw std::invalid_argument("a run of the calibration needs " + std::to_string(d) + " finite parameters and " +
                                  std::to_string(m) + " finite outputs");
    (r.level == Level::cheap ? cheap_count : expensive_count) += 1;
  }
  if (expensive_count < 2) throw std::invalid_argument("the surrogates need at least 2 expensive runs");
  if (cheap_count == 1) throw std::invalid_argument("the cheap level needs at least 2 runs, or none");
  two_levels_ = cheap_count > 0;
  LevelData cheap{Eigen::MatrixXd(cheap_count, d), Eigen::VectorXd(cheap_count)};
  LevelData expensive{Eigen::MatrixXd(expensive_count, d), Eigen::VectorXd(expensive_count)};
  models_.clear();
  noise_.clear();
  for (Eigen::Index j = 0; j < m; ++j) {
    Eigen::Index c = 0, e = 0;
    for (const auto& r : runs) {
      LevelData& level = r.level == Level::cheap ? cheap : expensive;
      Eigen::Index& k = r.level == Level::cheap ? c : e;
      level.points.row(k) = r.parameters.transpose();
      level.values(k) = r.outputs(j);
      ++k;
    }
    models_.emplace_back(bounds_, kind_, search_);
    models_.back().fit(cheap, expensive);
    noise_.push_back(models_.back().expensive_noise_variance());
  }
  incumbent_ = std::numeric_limits<double>::infinity();
  for (const auto& r : runs)
    if (r.level == Level::expensive) incumbent_ = std::min(incumbent_, predict(r.parameters).mean);
}

std::vector<Prediction> MisfitSurrogate::predict_outputs(const Eigen::VectorXd& point) const {
  if (models_.empty()) throw std::logic_error("MisfitSurrogate::predict before fit");
  std::vector<Prediction> out;
  for (const auto& model : models_) out.push_back(model.predict(point));
  return out;
}

MisfitPrediction MisfitSurrogate::predict(const Eigen::VectorXd& point) const {
  return misfit_of(predict_outputs(point));
}

MisfitPrediction MisfitSurrogate::misfit_of(std::span<const Prediction> outputs) const {
  return predict_misfit(outputs, noise_, targets_);
}

double MisfitSurrogate::variance_share(const Eigen::VectorXd& point, Level level) const {
  double total = 0.0, removed = 0.0;
  for (std::size_t j = 0; j < models_.size(); ++j) {
    const CoKriging& model = models_[j];
    const double s2 = targets_[j].scale * targets_[j].scale;
    // What a noisy observation at the point leaves of a variance v: v n / (v + n).
    const auto removed_by_run = [](double v, double n) { return v + n > 0.0 ? v * v / (v + n) : 0.0; };
    total += model.predict(point).variance / s2;
    const Prediction delta = model.difference().predict(point);
    double r = 0.0;
    if (model.has_cheap_level()) {
      const double rho2 = model.scale_factor() * model.scale_factor();
      r += rho2 * removed_by_run(model.predict_cheap(point).variance, model.cheap_noise_variance());
    }
    if (level == Level::expensive) r += removed_by_run(delta.variance, model.expensive_noise_variance());
    removed += r / s2;
  }
  return total > 0.0 ? removed / total : 0.0;
}

Eigen::VectorXd minimise_predicted_misfit(const MisfitSurrogate& surrogate, std::span<const Evaluation> runs,
                                          int global_evaluations) {
  std::vector<Eigen::VectorXd> starts;
  double best = std::numeric_limits<double>::infinity();
  for (const auto& r : runs) {
    if (r.level != Level::expensive) continue;
    const double value = surrogate.predict(r.parameters).mean;
    if (value < best) best = value, starts.assign(1, r.parameters);
  }
  BoxSearch search;
  search.global_evaluations = global_evaluations;
  return maximise_over_box([&](const Eigen::VectorXd& x) { return -surrogate.predict(x).mean; }, surrogate.bounds(),
                           starts, search)
      .point;
}

}  // namespace mfdem::calibration
