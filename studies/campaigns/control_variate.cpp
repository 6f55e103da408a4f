#include "studies/campaigns/control_variate.hpp"

#include <gsl/gsl_cdf.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "studies/campaigns/paired_statistics.hpp"

namespace mfdem::campaigns {

double control_variate_optimal_ratio(double correlation, double cost_ratio) {
  const double rho2 = correlation * correlation;
  if (rho2 >= 1.0) return std::numeric_limits<double>::infinity();
  return std::sqrt(cost_ratio * rho2 / (1.0 - rho2));
}

double control_variate_variance_ratio(double correlation, double cost_ratio, double ratio) {
  const double rho2 = correlation * correlation;
  return (1.0 - (1.0 - 1.0 / ratio) * rho2) * (1.0 + ratio / cost_ratio);
}

ControlVariateEstimate control_variate_estimate(const std::vector<double>& reference,
                                                const std::vector<double>& cheap_paired,
                                                const std::vector<double>& cheap_extra, double reference_cost,
                                                double cheap_cost, double plain_cost) {
  if (reference.size() != cheap_paired.size())
    throw std::invalid_argument("control_variate_estimate: the reference and cheap runs are not paired");
  if (reference.size() < 3)
    throw std::invalid_argument("control_variate_estimate: fewer than 3 paired runs (alpha and rho need them)");
  if (!(reference_cost > 0.0) || !(cheap_cost > 0.0) || plain_cost < 0.0)
    throw std::invalid_argument("control_variate_estimate: a run's cost must be > 0");
  ControlVariateEstimate e;
  e.n = reference.size();
  e.m = e.n + cheap_extra.size();
  e.plain_mean = mean_of(reference);
  e.cheap_mean_paired = mean_of(cheap_paired);
  double sum_cheap = e.cheap_mean_paired * double(e.n);
  for (double x : cheap_extra) sum_cheap += x;
  e.cheap_mean_all = sum_cheap / double(e.m);
  double cov = 0.0, var_hi = 0.0, var_lo = 0.0;
  for (std::size_t k = 0; k < e.n; ++k) {
    const double a = reference[k] - e.plain_mean, b = cheap_paired[k] - e.cheap_mean_paired;
    cov += a * b;
    var_hi += a * a;
    var_lo += b * b;
  }
  const double dof = double(e.n - 1);
  cov /= dof;
  var_hi /= dof;
  var_lo /= dof;
  if (!(var_lo > 0.0)) throw std::invalid_argument("control_variate_estimate: the cheap output has no spread");
  e.alpha = cov / var_lo;
  e.correlation = var_hi > 0.0 ? cov / std::sqrt(var_hi * var_lo) : 0.0;
  e.sd_reference = std::sqrt(var_hi);
  double all_lo = 0.0;
  for (double x : cheap_paired) all_lo += (x - e.cheap_mean_all) * (x - e.cheap_mean_all);
  for (double x : cheap_extra) all_lo += (x - e.cheap_mean_all) * (x - e.cheap_mean_all);
  e.sd_cheap = std::sqrt(all_lo / double(e.m - 1));
  e.estimate = e.plain_mean + e.alpha * (e.cheap_mean_all - e.cheap_mean_paired);
  const double rho2 = e.correlation * e.correlation;
  e.plain_variance = var_hi / double(e.n);
  e.variance = e.plain_variance * (1.0 - (1.0 - double(e.n) / double(e.m)) * rho2);
  // alpha is estimated from the paired runs too: one more degree of freedom spent.
  e.half_width = gsl_cdf_tdist_Pinv(0.975, double(e.n - 2)) * std::sqrt(e.variance);
  e.plain_half_width = gsl_cdf_tdist_Pinv(0.975, dof) * std::sqrt(e.plain_variance);
  e.cost_ratio = reference_cost / cheap_cost;
  e.optimal_ratio = control_variate_optimal_ratio(e.correlation, e.cost_ratio);
  e.variance_ratio_optimal = std::isfinite(e.optimal_ratio) && e.optimal_ratio > 1.0
                                 ? control_variate_variance_ratio(e.correlation, e.cost_ratio, e.optimal_ratio)
                                 : control_variate_variance_ratio(e.correlation, e.cost_ratio, 1.0);
  if (!std::isfinite(e.optimal_ratio)) e.variance_ratio_optimal = 0.0;
  e.variance_ratio_as_run =
      control_variate_variance_ratio(e.correlation, e.cost_ratio, double(e.m) / double(e.n));
  if (plain_cost > 0.0) {
    e.variance_ratio_optimal *= reference_cost / plain_cost;
    e.variance_ratio_as_run *= reference_cost / plain_cost;
  }
  return e;
}

}  // namespace mfdem::campaigns
