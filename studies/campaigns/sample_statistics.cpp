#include "studies/campaigns/sample_statistics.hpp"

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace mfdem::campaigns {

Interval bootstrap_mean_interval(const std::vector<double>& values, const BootstrapSettings& settings) {
  const std::size_t n = values.size();
  if (n < 2) throw std::invalid_argument("bootstrap_mean_interval: fewer than 2 values");
  if (settings.resamples < 2 || !(settings.level > 0.0 && settings.level < 1.0))
    throw std::invalid_argument("bootstrap_mean_interval: resamples < 2 or level outside (0, 1)");
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), &gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(settings.seed));
  std::vector<double> means(settings.resamples);
  for (double& m : means) {
    double sum = 0.0;
    for (std::size_t k = 0; k < n; ++k) sum += values[gsl_rng_uniform_int(rng.get(), static_cast<unsigned long>(n))];
    m = sum / double(n);
  }
  std::sort(means.begin(), means.end());
  // The quantile at probability p: linear between the order statistics around p (R's type 7).
  const auto quantile = [&](double p) {
    const double at = p * double(means.size() - 1);
    const auto below = static_cast<std::size_t>(std::floor(at));
    const std::size_t above = std::min(below + 1, means.size() - 1);
    return means[below] + (at - double(below)) * (means[above] - means[below]);
  };
  return {quantile(0.5 * (1.0 - settings.level)), quantile(0.5 * (1.0 + settings.level))};
}

std::optional<std::size_t> seeds_for_relative_half_width(const MeanInterval& so_far, double relative_half_width,
                                                          std::size_t cap) {
  if (so_far.n < 2 || so_far.mean == 0.0 || !(relative_half_width > 0.0)) return std::nullopt;
  const double target = relative_half_width * std::abs(so_far.mean);
  const auto half_width = [&](std::size_t n) {
    return gsl_cdf_tdist_Pinv(0.975, double(n - 1)) * so_far.standard_deviation / std::sqrt(double(n));
  };
  if (half_width(2) <= target) return std::size_t{2};
  if (half_width(cap) > target) return cap;
  // The half-width falls monotonically with n: bisect for the first n that meets the target.
  std::size_t low = 2, high = cap;  // half_width(low) > target >= half_width(high)
  while (high - low > 1) {
    const std::size_t mid = low + (high - low) / 2;
    (half_width(mid) <= target ? high : low) = mid;
  }
  return high;
}

OutputSummary summarise_output(const std::vector<double>& values, const BootstrapSettings& bootstrap,
                               double requested_relative_half_width) {
  OutputSummary s;
  s.mean = mean_interval(values);
  if (values.size() >= 2) s.bootstrap = bootstrap_mean_interval(values, bootstrap);
  for (std::size_t n = 1; n <= values.size(); ++n)
    s.running.push_back(mean_interval(std::vector<double>(values.begin(), values.begin() + long(n))));
  s.requested_width = requested_relative_half_width;
  if (requested_relative_half_width > 0.0) s.seeds_for_width = seeds_for_relative_half_width(s.mean, requested_relative_half_width);
  return s;
}

}  // namespace mfdem::campaigns
