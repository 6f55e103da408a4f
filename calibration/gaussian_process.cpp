#include "calibration/gaussian_process.hpp"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "calibration/sobol_design.hpp"

namespace mfdem::calibration {
namespace {

constexpr double kFirstJitter = 1e-10;  // x the mean diagonal; raised tenfold until K factorises
constexpr double kLastJitter = 1e-2;

Hyperparameters from_theta(const Eigen::VectorXd& theta, int d) {
  Hyperparameters h;
  h.length_scales = theta.head(d).array().exp();
  h.signal_variance = std::exp(theta(d));
  h.noise_variance = std::exp(theta(d + 1));
  return h;
}

}  // namespace

GaussianProcess::GaussianProcess(std::vector<Bounds> bounds, KernelKind kind, HyperparameterSearch search)
    : bounds_(std::move(bounds)), kind_(kind), search_(search) {
  if (bounds_.empty()) throw std::invalid_argument("a Gaussian process needs at least one input");
  for (const auto& b : bounds_)
    if (!(b.upper > b.lower) || !std::isfinite(b.lower) || !std::isfinite(b.upper))
      throw std::invalid_argument("a Gaussian process's input bound needs finite lower < upper");
}

Eigen::VectorXd GaussianProcess::to_unit(const Eigen::VectorXd& point) const {
  Eigen::VectorXd u(point.size());
  for (Eigen::Index a = 0; a < point.size(); ++a)
    u(a) = (point(a) - bounds_[a].lower) / (bounds_[a].upper - bounds_[a].lower);
  return u;
}

void GaussianProcess::take_data(const Eigen::MatrixXd& points, const Eigen::VectorXd& values,
                                std::optional<OutputScale> scale) {
  const auto d = static_cast<Eigen::Index>(bounds_.size());
  if (points.rows() < 2) throw std::invalid_argument("a Gaussian process needs at least 2 points");
  if (points.cols() != d || values.size() != points.rows())
    throw std::invalid_argument("Gaussian process data: points must be n x " + std::to_string(d) +
                                " with n values");
  if (!points.allFinite() || !values.allFinite())
    throw std::invalid_argument("Gaussian process data: a point or value is not finite");
  notes_.clear();
  x_.resize(points.rows(), d);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    x_.row(i) = to_unit(points.row(i).transpose()).transpose();
    if ((x_.row(i).array() < -1e-12).any() || (x_.row(i).array() > 1.0 + 1e-12).any())
      throw std::invalid_argument("Gaussian process data: point " + std::to_string(i) + " lies outside the bounds");
  }
  y_mean_ = values.mean();
  const double spread = std::sqrt((values.array() - y_mean_).square().sum() / double(values.size() - 1));
  // A constant output has no scale of its own: kept unscaled, the process predicts the constant.
  y_scale_ = spread > 0.0 ? spread : 1.0;
  if (!(spread > 0.0)) notes_.push_back("the output is constant over the points: the surrogate predicts that constant");
  if (scale) {
    if (!(scale->scale > 0.0) || !std::isfinite(scale->mean))
      throw std::invalid_argument("Gaussian process output scale: a finite mean and a scale > 0 expected");
    y_mean_ = scale->mean, y_scale_ = scale->scale;
  }
  y_ = (values.array() - y_mean_) / y_scale_;
  int repeated = 0;
  for (Eigen::Index i = 0; i < x_.rows(); ++i)
    for (Eigen::Index j = 0; j < i; ++j)
      if (x_.row(i) == x_.row(j)) {
        ++repeated;
        break;
      }
  if (repeated > 0)
    notes_.push_back(std::to_string(repeated) + " points repeat earlier ones (replicates): their scatter is the noise");
}

Eigen::MatrixXd GaussianProcess::covariance(const Hyperparameters& h) const {
  const Eigen::Index n = x_.rows();
  Eigen::MatrixXd k(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    k(i, i) = h.signal_variance + h.noise_variance;
    for (Eigen::Index j = 0; j < i; ++j)
      k(i, j) = k(j, i) = h.signal_variance * kernel_correlation(kind_, scaled_distance(x_.row(i).transpose(),
                                                                                        x_.row(j).transpose(),
                                                                                        h.length_scales));
  }
  return k;
}

void GaussianProcess::factorise() {
  const Eigen::MatrixXd k = covariance(h_);
  const double diagonal = k.diagonal().mean();
  jitter_ = 0.0;
  factor_.compute(k);
  for (double j = kFirstJitter; factor_.info() != Eigen::Success && j <= kLastJitter; j *= 10.0) {
    jitter_ = j * diagonal;
    factor_.compute(k + jitter_ * Eigen::MatrixXd::Identity(k.rows(), k.cols()));
  }
  if (factor_.info() != Eigen::Success)
    throw std::runtime_error("Gaussian process: the covariance is not positive definite even with a jitter of 1e-2 "
                             "of its diagonal (repeated points with a noise variance of 0?)");
  alpha_ = factor_.solve(y_);
  const Eigen::MatrixXd l = factor_.matrixL();
  log_likelihood_ = -0.5 * y_.dot(alpha_) - l.diagonal().array().log().sum() -
                    0.5 * double(y_.size()) * std::log(2.0 * std::numbers::pi);
}

void GaussianProcess::fit(const Eigen::MatrixXd& points, const Eigen::VectorXd& values, const Hyperparameters& h,
                          std::optional<OutputScale> scale) {
  if (h.length_scales.size() != static_cast<Eigen::Index>(bounds_.size()) || !(h.signal_variance > 0.0) ||
      !(h.noise_variance >= 0.0) || !(h.length_scales.array() > 0.0).all())
    throw std::invalid_argument("Gaussian process hyperparameters: one positive length scale per input, a "
                                "positive signal variance and a noise variance >= 0");
  take_data(points, values, scale);
  h_ = h;
  factorise();
}

double GaussianProcess::log_likelihood_at(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) const {
  const auto d = static_cast<Eigen::Index>(bounds_.size());
  const Eigen::Index n = x_.rows();
  const Hyperparameters h = from_theta(theta, static_cast<int>(d));
  Eigen::MatrixXd k = covariance(h);
  Eigen::LLT<Eigen::MatrixXd> llt(k);
  if (llt.info() != Eigen::Success) {
    k.diagonal().array() += kLastJitter * k.diagonal().mean();
    llt.compute(k);
    if (llt.info() != Eigen::Success) {
      if (gradient) gradient->setZero(theta.size());
      return -std::numeric_limits<double>::max();
    }
  }
  const Eigen::VectorXd alpha = llt.solve(y_);
  const Eigen::MatrixXd l = llt.matrixL();
  const double value = -0.5 * y_.dot(alpha) - l.diagonal().array().log().sum() -
                       0.5 * double(n) * std::log(2.0 * std::numbers::pi);
  if (gradient) {
    // d log p / d theta_j = tr((alpha alpha^T - K^-1) dK/dtheta_j) / 2 (R&W eq. 5.9).
    const Eigen::MatrixXd w = alpha * alpha.transpose() - llt.solve(Eigen::MatrixXd::Identity(n, n));
    gradient->setZero(d + 2);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = 0; j < n; ++j) {
        const Eigen::VectorXd diff = (x_.row(i) - x_.row(j)).transpose().array() / h.length_scales.array();
        const double r = diff.norm();
        const double corr = kernel_correlation(kind_, r);
        const double factor = h.signal_variance * kernel_log_scale_factor(kind_, r);
        for (Eigen::Index a = 0; a < d; ++a) (*gradient)(a) += 0.5 * w(i, j) * factor * diff(a) * diff(a);
        (*gradient)(d) += 0.5 * w(i, j) * h.signal_variance * corr;
      }
    (*gradient)(d + 1) = 0.5 * h.noise_variance * w.trace();
  }
  return value;
}

void GaussianProcess::fit(const Eigen::MatrixXd& points, const Eigen::VectorXd& values) {
  search(points, values, std::nullopt);
}

void GaussianProcess::fit(const Eigen::MatrixXd& points, const Eigen::VectorXd& values, OutputScale scale) {
  search(points, values, scale);
}

void GaussianProcess::search(const Eigen::MatrixXd& points, const Eigen::VectorXd& values,
                             std::optional<OutputScale> scale) {
  take_data(points, values, scale);
  const auto d = static_cast<int>(bounds_.size());
  // The search box on log scales, and its starts: the first points of an unshifted Sobol design.
  std::vector<Bounds> box;
  for (int a = 0; a < d; ++a) box.push_back({std::log(search_.shortest_length), std::log(search_.longest_length)});
  box.push_back({std::log(search_.smallest_signal), std::log(search_.largest_signal)});
  const bool fixed_noise = search_.smallest_noise == search_.largest_noise;
  const double low_noise = std::log(search_.smallest_noise);
  box.push_back({low_noise, fixed_noise ? low_noise + 1.0 : std::log(search_.largest_noise)});
  std::vector<double> lower, upper;
  for (const auto& b : box) lower.push_back(b.lower), upper.push_back(b.upper);
  if (fixed_noise) upper.back() = lower.back();  // NLopt keeps a variable with equal bounds fixed
  auto starts = sobol_design(box, std::max(1, search_.starts));
  const auto objective = [](const std::vector<double>& t, std::vector<double>& g, void* self) {
    const auto* gp = static_cast<const GaussianProcess*>(self);
    const Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(t.data(), static_cast<Eigen::Index>(t.size()));
    Eigen::VectorXd gradient;
    const double value = gp->log_likelihood_at(theta, g.empty() ? nullptr : &gradient);
    for (std::size_t k = 0; k < g.size(); ++k) g[k] = gradient(static_cast<Eigen::Index>(k));
    return value;
  };
  if (search_.global_evaluations > 0) {
    // DIRECT-L needs a box with some width on every axis: a fixed noise stays out of it.
    const unsigned free = static_cast<unsigned>(fixed_noise ? d + 1 : d + 2);
    nlopt::opt global(nlopt::GN_DIRECT_L, free);
    global.set_lower_bounds(std::vector<double>(lower.begin(), lower.begin() + free));
    global.set_upper_bounds(std::vector<double>(upper.begin(), upper.begin() + free));
    global.set_maxeval(search_.global_evaluations);
    struct Fixed {
      const GaussianProcess* gp;
      double noise;
      bool fixed;
    } context{this, lower.back(), fixed_noise};
    global.set_max_objective(
        [](const std::vector<double>& t, std::vector<double>&, void* data) {
          const auto* c = static_cast<const Fixed*>(data);
          Eigen::VectorXd theta(static_cast<Eigen::Index>(t.size() + (c->fixed ? 1 : 0)));
          for (std::size_t k = 0; k < t.size(); ++k) theta(static_cast<Eigen::Index>(k)) = t[k];
          if (c->fixed) theta(theta.size() - 1) = c->noise;
          return c->gp->log_likelihood_at(theta, nullptr);
        },
        &context);
    std::vector<double> point(free);
    for (unsigned k = 0; k < free; ++k) point[k] = 0.5 * (lower[k] + upper[k]);
    double value = 0.0;
    try {
      global.optimize(point, value);
    } catch (const std::exception&) {
      // DIRECT-L stopped early (round-off): its best point so far is a start as good as any.
    }
    if (fixed_noise) point.push_back(lower.back());
    starts.insert(starts.begin(), point);
  }

  nlopt::opt local(nlopt::LD_LBFGS, static_cast<unsigned>(d + 2));
  local.set_lower_bounds(lower);
  local.set_upper_bounds(upper);
  local.set_maxeval(search_.evaluations_per_start);
  local.set_ftol_rel(1e-10);
  local.set_max_objective(objective, this);
  double best = -std::numeric_limits<double>::infinity();
  std::vector<double> best_theta = starts.front();
  for (auto start : starts) {
    if (fixed_noise) start.back() = lower.back();
    double value = -std::numeric_limits<double>::infinity();
    try {
      local.optimize(start, value);
    } catch (const std::exception&) {
      // A search stopped by round-off keeps its last point; its value is compared as any other.
      Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(start.data(), static_cast<Eigen::Index>(start.size()));
      value = log_likelihood_at(theta, nullptr);
    }
    if (value > best) best = value, best_theta = start;
  }
  h_ = from_theta(Eigen::Map<const Eigen::VectorXd>(best_theta.data(), static_cast<Eigen::Index>(best_theta.size())),
                  d);
  factorise();
}

Prediction GaussianProcess::predict(const Eigen::VectorXd& point) const {
  if (alpha_.size() == 0) throw std::logic_error("GaussianProcess::predict before fit");
  if (point.size() != static_cast<Eigen::Index>(bounds_.size()) || !point.allFinite())
    throw std::invalid_argument("Gaussian process prediction: a finite point of the inputs' dimension expected");
  const Eigen::VectorXd u = to_unit(point);
  Eigen::VectorXd k(x_.rows());
  for (Eigen::Index i = 0; i < x_.rows(); ++i)
    k(i) = h_.signal_variance * kernel_correlation(kind_, scaled_distance(u, x_.row(i).transpose(), h_.length_scales));
  const Eigen::VectorXd v = factor_.matrixL().solve(k);
  Prediction p;
  p.mean = y_mean_ + y_scale_ * k.dot(alpha_);
  p.variance = y_scale_ * y_scale_ * std::max(0.0, h_.signal_variance - v.squaredNorm());
  return p;
}

LeaveOneOut GaussianProcess::leave_one_out() const {
  if (alpha_.size() == 0) throw std::logic_error("GaussianProcess::leave_one_out before fit");
  const Eigen::Index n = x_.rows();
  const Eigen::MatrixXd inverse = factor_.solve(Eigen::MatrixXd::Identity(n, n));
  LeaveOneOut loo;
  loo.mean.resize(n);
  loo.variance.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    loo.mean(i) = y_mean_ + y_scale_ * (y_(i) - alpha_(i) / inverse(i, i));
    loo.variance(i) = y_scale_ * y_scale_ / inverse(i, i);
  }
  return loo;
}

std::vector<GaussianProcess> fit_outputs(const std::vector<Bounds>& bounds, const Eigen::MatrixXd& points,
                                         const Eigen::MatrixXd& values, KernelKind kind,
                                         const HyperparameterSearch& search) {
  if (values.rows() != points.rows())
    throw std::invalid_argument("Gaussian process outputs: one row of values per point expected");
  std::vector<GaussianProcess> processes;
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    processes.emplace_back(bounds, kind, search);
    processes.back().fit(points, values.col(j));
  }
  return processes;
}

}  // namespace mfdem::calibration
