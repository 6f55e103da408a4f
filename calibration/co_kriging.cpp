#include "calibration/co_kriging.hpp"

#include <nlopt.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

namespace mfdem::calibration {
namespace {

constexpr int kRhoGrid = 17;  // points of the scale factor's first, coarse search

double noise_in_units(const GaussianProcess& gp) {
  const double s = gp.output_scale().scale;
  return gp.hyperparameters().noise_variance * s * s;
}

}  // namespace

CoKriging::CoKriging(std::vector<Bounds> bounds, KernelKind kind, HyperparameterSearch search)
    : bounds_(std::move(bounds)), kind_(kind), search_(search) {}

void CoKriging::fit(const Eigen::MatrixXd& points, const Eigen::VectorXd& values) {
  fit(LevelData{Eigen::MatrixXd(0, points.cols()), Eigen::VectorXd(0)}, LevelData{points, values});
}

void CoKriging::fit(const LevelData& cheap, const LevelData& expensive) {
  cheap_.reset();
  delta_.reset();
  rho_ = 0.0;
  if (cheap.size() == 0) {
    delta_.emplace(bounds_, kind_, search_);
    delta_->fit(expensive.points, expensive.values);
    return;
  }
  cheap_.emplace(bounds_, kind_, search_);
  cheap_->fit(cheap.points, cheap.values);
  if (expensive.size() < 2) throw std::invalid_argument("co-kriging needs at least 2 expensive runs");
  Eigen::VectorXd m(expensive.size());
  for (Eigen::Index i = 0; i < expensive.size(); ++i) m(i) = cheap_->predict(expensive.points.row(i).transpose()).mean;

  // One standardisation for every residual set: the expensive outputs' own.
  const Eigen::VectorXd& y = expensive.values;
  const double spread = std::sqrt((y.array() - y.mean()).square().sum() / double(y.size() - 1));
  const double scale = spread > 0.0 ? spread : 1.0;
  const auto likelihood = [&](double rho) {
    const Eigen::VectorXd r = y - rho * m;
    GaussianProcess gp(bounds_, kind_, search_);
    gp.fit(expensive.points, r, OutputScale{r.mean(), scale});
    return gp.log_marginal_likelihood();
  };
  // Centre the search on the least-squares slope of y on m (with an intercept).
  const double m_mean = m.mean();
  const double m_var = (m.array() - m_mean).square().sum();
  const double slope = m_var > 0.0 ? ((m.array() - m_mean) * (y.array() - y.mean())).sum() / m_var : 0.0;
  const double half_width = std::max(1.0, 2.0 * std::abs(slope));
  const double low = slope - half_width, high = slope + half_width;
  double best_rho = slope, best = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < kRhoGrid; ++k) {
    const double rho = low + (high - low) * k / (kRhoGrid - 1);
    const double value = likelihood(rho);
    if (value > best) best = value, best_rho = rho;
  }
  nlopt::opt local(nlopt::LN_BOBYQA, 1);
  local.set_lower_bounds(std::vector<double>{low});
  local.set_upper_bounds(std::vector<double>{high});
  local.set_initial_step(std::vector<double>{(high - low) / (kRhoGrid - 1) / 2.0});
  local.set_xtol_abs(1e-6 * half_width);
  local.set_maxeval(60);
  std::function<double(double)> objective = likelihood;
  local.set_max_objective(
      [](const std::vector<double>& x, std::vector<double>&, void* f) {
        return (*static_cast<std::function<double(double)>*>(f))(x[0]);
      },
      &objective);
  std::vector<double> x{best_rho};
  double value = best;
  try {
    local.optimize(x, value);
  } catch (const std::exception&) {
    // Stopped by round-off: its last point is compared below as any other.
    value = likelihood(x[0]);
  }
  rho_ = value > best ? x[0] : best_rho;
  const Eigen::VectorXd r = y - rho_ * m;
  delta_.emplace(bounds_, kind_, search_);
  delta_->fit(expensive.points, r, OutputScale{r.mean(), scale});
}

Prediction CoKriging::predict(const Eigen::VectorXd& point) const {
  if (!delta_) throw std::logic_error("CoKriging::predict before fit");
  Prediction p = delta_->predict(point);
  if (cheap_) {
    const Prediction c = cheap_->predict(point);
    p.mean += rho_ * c.mean;
    p.variance += rho_ * rho_ * c.variance;
  }
  return p;
}

Prediction CoKriging::predict_cheap(const Eigen::VectorXd& point) const {
  if (!cheap_) throw std::logic_error("CoKriging::predict_cheap without cheap runs");
  return cheap_->predict(point);
}

double CoKriging::cheap_noise_variance() const {
  if (!cheap_) throw std::logic_error("CoKriging::cheap_noise_variance without cheap runs");
  return noise_in_units(*cheap_);
}

double CoKriging::expensive_noise_variance() const {
  if (!delta_) throw std::logic_error("CoKriging::expensive_noise_variance before fit");
  return noise_in_units(*delta_);
}

}  // namespace mfdem::calibration
