#pragma once
// The surrogates of a calibration: one co-kriging model per output (calibration/co_kriging.hpp),
// over runs at one or two levels of fidelity, and the misfit they predict (calibration/misfit.hpp).
#include <span>
#include <vector>

#include "calibration/co_kriging.hpp"
#include "calibration/misfit.hpp"

namespace mfdem::calibration {

enum class Level { cheap = 0, expensive = 1 };

// One finished run: where, at which level, and its outputs (one per target).
struct Evaluation {
  Eigen::VectorXd parameters;
  Level level = Level::expensive;
  Eigen::VectorXd outputs;
};

class MisfitSurrogate {
 public:
  MisfitSurrogate(std::vector<Bounds> bounds, std::vector<Target> targets, KernelKind kind = KernelKind::matern52,
                  HyperparameterSearch search = {});

  // Fits every output's model on the runs. Needs 2 expensive runs, and 2 cheap ones if any.
  // Throws std::invalid_argument for a run whose outputs are not one finite value per target.
  void fit(std::span<const Evaluation> runs);

  // The expensive level's outputs and misfit at a point.
  std::vector<Prediction> predict_outputs(const Eigen::VectorXd& point) const;
  MisfitPrediction predict(const Eigen::VectorXd& point) const;
  // The misfit of outputs already predicted at a point (predict_outputs): no second prediction.
  MisfitPrediction misfit_of(std::span<const Prediction> outputs) const;

  // The best predicted misfit at the points run at the expensive level: expected improvement's
  // incumbent. Cheap runs never set it (emukit issue 468: an incumbent from cheap runs stalls the
  // search).
  double incumbent() const { return incumbent_; }
  // The share of the expensive prediction's variance (summed over outputs, each in units of its
  // target's scale) that one more run at `level` at this point would remove: a cheap run removes
  // rho^2 v_c^2 / (v_c + n_c) per output, an expensive run (made with its cheap twin, so that the
  // design stays nested) that and v_d^2 / (v_d + n_d) besides.
  double variance_share(const Eigen::VectorXd& point, Level level) const;
  bool two_levels() const { return two_levels_; }

  const std::vector<Bounds>& bounds() const { return bounds_; }
  KernelKind kind() const { return kind_; }
  const HyperparameterSearch& search() const { return search_; }
  const std::vector<Target>& targets() const { return targets_; }
  const std::vector<CoKriging>& outputs() const { return models_; }

 private:
  std::vector<Bounds> bounds_;
  std::vector<Target> targets_;
  KernelKind kind_;
  HyperparameterSearch search_;
  std::vector<CoKriging> models_;
  std::vector<double> noise_;  // expensive observation noise variance of each output
  double incumbent_ = 0.0;
  bool two_levels_ = false;
};

// The minimiser of the predicted mean misfit over the bounds (NLopt DIRECT-L, then BOBYQA from
// its best point and from the best expensive run): the point a surrogate calibration returns.
Eigen::VectorXd minimise_predicted_misfit(const MisfitSurrogate& surrogate, std::span<const Evaluation> runs,
                                          int global_evaluations = 0);

}  // namespace mfdem::calibration
