#pragma once
// Gaussian-process regression (Rasmussen & Williams 2006, ch. 2 and 5): a surrogate of a noisy,
// expensive output that says how sure it is.
//
// The model: inputs scaled to the unit box of the bounds, the output standardised (mean 0, unit
// sample variance), y = f(x) + e with f ~ GP(0, k), k an anisotropic kernel (kernel.hpp) of signal
// variance s2 and length scales l_i (in unit-box lengths), e ~ N(0, s2_n) the observation noise
// (the packing seed's scatter; replicates at one point allowed). With K = k(X, X) + s2_n I = L L^T:
//   mean(x)     = k(x, X) alpha,  alpha = K^-1 y                            (R&W eq. 2.25)
//   variance(x) = k(x, x) - v^T v, v = L^-1 k(X, x)                         (R&W eq. 2.26)
//   log p(y)    = -y^T alpha / 2 - sum log L_ii - n log(2 pi) / 2           (R&W eq. 2.30)
//   leave-one-out: mean_-i = y_i - [K^-1 y]_i / [K^-1]_ii, variance_-i = 1 / [K^-1]_ii (eq. 5.12)
// both back in the output's units. Hyperparameters (log l_i, log s2, log s2_n) maximise log p(y):
// a global search, then local searches with its analytic gradient (R&W eq. 5.9) from several starts.
#include <Eigen/Dense>

#include <optional>
#include <string>
#include <vector>

#include "calibration/kernel.hpp"
#include "calibration/latin_hypercube.hpp"
#include "calibration/surrogate.hpp"

namespace mfdem::calibration {

struct Hyperparameters {
  Eigen::VectorXd length_scales;  // per input, in unit-box lengths
  double signal_variance = 1.0;   // of the standardised output
  double noise_variance = 0.0;    // of the standardised output
};

// The search box of the hyperparameters (standardised output, unit-box inputs) and its starts.
struct HyperparameterSearch {
  double shortest_length = 1e-2, longest_length = 1e2;
  double smallest_signal = 1e-2, largest_signal = 1e2;
  // The noise variance's range; set both to the same value to fix it (a deterministic output:
  // 1e-10, for interpolation up to round-off).
  double smallest_noise = 1e-8, largest_noise = 1.0;
  // A global search (NLopt's DIRECT-L, derivative-free) over the box first, then local L-BFGS
  // searches from its best point and from the first points of a Sobol design; the best is kept.
  int global_evaluations = 300;
  int starts = 8;
  int evaluations_per_start = 200;
};

// The output's standardisation: y_standard = (y - mean) / scale.
struct OutputScale {
  double mean = 0.0, scale = 1.0;
};

struct LeaveOneOut {
  Eigen::VectorXd mean, variance;  // predictions of each y_i from the others (variance with noise)
};

class GaussianProcess final : public Surrogate {
 public:
  GaussianProcess(std::vector<Bounds> bounds, KernelKind kind = KernelKind::matern52,
                  HyperparameterSearch search = {});

  // Fits the hyperparameters by maximum marginal likelihood, then the process. Throws
  // std::invalid_argument for fewer than 2 points, a point outside the bounds, a point or value
  // that is not finite, or points of the wrong dimension.
  void fit(const Eigen::MatrixXd& points, const Eigen::VectorXd& values) override;
  // The same search with the standardisation given: likelihoods of several data sets fitted with
  // one scale compare (co-kriging's choice of its scale factor).
  void fit(const Eigen::MatrixXd& points, const Eigen::VectorXd& values, OutputScale scale);
  // The process with the hyperparameters given (no search), and the standardisation when given
  // (else the data's mean and sample standard deviation).
  void fit(const Eigen::MatrixXd& points, const Eigen::VectorXd& values, const Hyperparameters& h,
           std::optional<OutputScale> scale = std::nullopt);

  Prediction predict(const Eigen::VectorXd& point) const override;
  LeaveOneOut leave_one_out() const;

  const Hyperparameters& hyperparameters() const { return h_; }
  OutputScale output_scale() const { return {y_mean_, y_scale_}; }
  double log_marginal_likelihood() const { return log_likelihood_; }  // of the standardised output
  // Added to the diagonal of K (standardised) for the Cholesky factor to exist: 0 normally.
  double jitter() const { return jitter_; }
  // What the fit had to do with its data (a constant output, repeated points), for the report.
  const std::vector<std::string>& notes() const { return notes_; }

  // log p(y) of the standardised data at hyperparameters theta = (log l_1..d, log s2, log s2_n)
  // and its gradient; for the search and its tests. Call after fit().
  double log_likelihood_at(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) const;

 private:
  std::vector<Bounds> bounds_;
  KernelKind kind_;
  HyperparameterSearch search_;
  Eigen::MatrixXd x_;             // n x d in the unit box
  Eigen::VectorXd y_;             // standardised
  double y_mean_ = 0.0, y_scale_ = 1.0;
  Hyperparameters h_;
  Eigen::LLT<Eigen::MatrixXd> factor_;
  Eigen::VectorXd alpha_;
  double log_likelihood_ = 0.0;
  double jitter_ = 0.0;
  std::vector<std::string> notes_;

  void take_data(const Eigen::MatrixXd& points, const Eigen::VectorXd& values, std::optional<OutputScale> scale);
  void search(const Eigen::MatrixXd& points, const Eigen::VectorXd& values, std::optional<OutputScale> scale);
  Eigen::VectorXd to_unit(const Eigen::VectorXd& point) const;
  Eigen::MatrixXd covariance(const Hyperparameters& h) const;  // k(X, X) + s2_n I
  void factorise();
};

// Several outputs of one model (the peak force and the contact force) as independent processes on
// the same points: column j of `values` (n x m) is fitted by the j-th process, each with its own
// hyperparameters.
std::vector<GaussianProcess> fit_outputs(const std::vector<Bounds>& bounds, const Eigen::MatrixXd& points,
                                         const Eigen::MatrixXd& values, KernelKind kind = KernelKind::matern52,
                                         const HyperparameterSearch& search = {});

}  // namespace mfdem::calibration
