#include "calibration/posterior.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace mfdem::calibration {
namespace {

// The q-quantile of a discrete distribution over sorted values: the first value whose cumulative
// weight reaches q, interpolated linearly within the cell.
double weighted_quantile(const std::vector<double>& values, const std::vector<double>& weights, double q) {
  const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  double below = 0.0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    const double next = below + weights[k] / total;
    if (next >= q) {
      if (k == 0 || weights[k] == 0.0) return values[k];
      const double t = (q - below) / (next - below);  // where in the step between k-1 and k
      return values[k - 1] + t * (values[k] - values[k - 1]);
    }
    below = next;
  }
  return values.back();
}

PosteriorSummary on_grid(const MisfitSurrogate& s, const PosteriorOptions& o) {
  const auto d = s.bounds().size();
  const int n = o.grid_points;
  std::vector<std::vector<double>> axis(d);
  for (std::size_t a = 0; a < d; ++a)
    for (int k = 0; k < n; ++k) axis[a].push_back(s.bounds()[a].lower + (s.bounds()[a].upper - s.bounds()[a].lower) * k / (n - 1));
  const std::size_t cells = d == 1 ? n : std::size_t(n) * n;
  std::vector<double> log_p(cells);
  Eigen::VectorXd x(static_cast<Eigen::Index>(d));
  for (std::size_t c = 0; c < cells; ++c) {
    x(0) = axis[0][c % n];
    if (d == 2) x(1) = axis[1][c / n];
    log_p[c] = log_likelihood(s, x, o.target_sd);
  }
  const auto top = std::max_element(log_p.begin(), log_p.end());
  PosteriorSummary summary;
  summary.method = "grid";
  summary.mode.resize(static_cast<Eigen::Index>(d));
  const std::size_t best = static_cast<std::size_t>(top - log_p.begin());
  summary.mode(0) = axis[0][best % n];
  if (d == 2) summary.mode(1) = axis[1][best / n];
  std::vector<std::vector<double>> marginal(d, std::vector<double>(n, 0.0));
  for (std::size_t c = 0; c < cells; ++c) {
    const double w = std::exp(log_p[c] - *top);
    marginal[0][c % n] += w;
    if (d == 2) marginal[1][c / n] += w;
  }
  const double tail = 0.5 * (1.0 - o.interval);
  for (std::size_t a = 0; a < d; ++a)
    summary.intervals.push_back({weighted_quantile(axis[a], marginal[a], tail), weighted_quantile(axis[a], marginal[a], 0.5),
                                 weighted_quantile(axis[a], marginal[a], 1.0 - tail)});
  return summary;
}

PosteriorSummary by_metropolis(const MisfitSurrogate& s, const PosteriorOptions& o) {
  const auto d = static_cast<Eigen::Index>(s.bounds().size());
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(o.seed));
  Eigen::VectorXd width(d), x(d);
  for (Eigen::Index a = 0; a < d; ++a) {
    width(a) = s.bounds()[a].upper - s.bounds()[a].lower;
    x(a) = s.bounds()[a].lower + 0.5 * width(a);
  }
  const auto inside = [&](const Eigen::VectorXd& p) {
    for (Eigen::Index a = 0; a < d; ++a)
      if (p(a) < s.bounds()[a].lower || p(a) > s.bounds()[a].upper) return false;
    return true;
  };
  double step = 0.1, log_p = log_likelihood(s, x, o.target_sd);
  PosteriorSummary summary;
  summary.method = "metropolis";
  summary.mode = x;
  double best = log_p;
  std::vector<std::vector<double>> kept(static_cast<std::size_t>(d));
  int accepted = 0, tried = 0;
  for (int k = 0; k < o.burn_in + o.samples; ++k) {
    Eigen::VectorXd proposal = x;
    for (Eigen::Index a = 0; a < d; ++a) proposal(a) += step * width(a) * gsl_ran_ugaussian(rng.get());
    const bool in = inside(proposal);
    const double candidate = in ? log_likelihood(s, proposal, o.target_sd) : -std::numeric_limits<double>::infinity();
    const bool accept = in && std::log(gsl_rng_uniform_pos(rng.get())) < candidate - log_p;
    if (accept) x = proposal, log_p = candidate;
    if (log_p > best) best = log_p, summary.mode = x;
    if (k < o.burn_in) {
      // Tune the step every 100 proposals towards an acceptance of about 0.3.
      accepted += accept, ++tried;
      if (tried == 100) {
        step *= accepted > 30 ? 1.3 : 0.75;
        accepted = tried = 0;
      }
      continue;
    }
    summary.acceptance += accept;
    for (Eigen::Index a = 0; a < d; ++a) kept[a].push_back(x(a));
  }
  summary.acceptance /= std::max(1, o.samples);
  const double tail = 0.5 * (1.0 - o.interval);
  for (auto& values : kept) {
    std::sort(values.begin(), values.end());
    const auto at = [&](double q) { return values[static_cast<std::size_t>(q * double(values.size() - 1))]; };
    summary.intervals.push_back({at(tail), at(0.5), at(1.0 - tail)});
  }
  return summary;
}

}  // namespace

double log_likelihood(const MisfitSurrogate& surrogate, const Eigen::VectorXd& point, const std::vector<double>& target_sd) {
  const auto outputs = surrogate.predict_outputs(point);
  double value = 0.0;
  for (std::size_t j = 0; j < outputs.size(); ++j) {
    // A floor of 1e-12 of the target's scale squared: a noise-free surrogate at a run with an
    // exact target would otherwise divide by zero.
    const double floor = 1e-12 * surrogate.targets()[j].scale * surrogate.targets()[j].scale;
    const double variance = std::max(outputs[j].variance + target_sd[j] * target_sd[j], floor);
    const double e = surrogate.targets()[j].value - outputs[j].mean;
    value += -0.5 * e * e / variance - 0.5 * std::log(variance);
  }
  return value;
}

PosteriorSummary calibration_posterior(const MisfitSurrogate& surrogate, const PosteriorOptions& options) {
  if (options.target_sd.size() != surrogate.targets().size())
    throw std::invalid_argument("posterior: one target standard deviation per target expected");
  for (double t : options.target_sd)
    if (!(t >= 0.0) || !std::isfinite(t)) throw std::invalid_argument("posterior: target standard deviations must be >= 0");
  if (!(options.interval > 0.0 && options.interval < 1.0)) throw std::invalid_argument("posterior: an interval in (0, 1)");
  if (surrogate.bounds().size() <= 2) {
    if (options.grid_points < 3) throw std::invalid_argument("posterior: at least 3 grid points per parameter");
    return on_grid(surrogate, options);
  }
  if (options.samples < 100) throw std::invalid_argument("posterior: at least 100 samples");
  return by_metropolis(surrogate, options);
}

}  // namespace mfdem::calibration
