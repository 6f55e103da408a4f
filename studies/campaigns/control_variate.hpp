#pragma once
// The cheap model as a control variate: the reference model's mean over packings estimated from
// n reference runs and m >= n runs of a cheap model, n of them on the same seeds (paired) and
// m - n on more seeds. The multifidelity Monte Carlo estimator with one cheap model
// (Peherstorfer, Willcox & Gunzburger 2016, SIAM J. Sci. Comput. 38(5) A3163-A3194,
// doi:10.1137/15M1046472):
//
//   E = mean_n(hi) + alpha (mean_m(lo) - mean_n(lo)),   alpha = cov(hi, lo) / var(lo)
//
// with mean_n over the paired seeds and mean_m over every cheap run. At that alpha its variance is
//   var(E) = var(hi) / n x (1 - (1 - n/m) rho^2)          (rho: the paired correlation)
// For runs costing w_hi and w_lo, a budget p = n w_hi + m w_lo is spent best with
//   m / n = r* = sqrt(w_hi rho^2 / (w_lo (1 - rho^2)))
// and the variance against reference runs alone of the same cost is then
//   (1 - (1 - 1/r) rho^2) (1 + r w_lo / w_hi)              (below 1: the cheap runs pay).
// With the paper's cost ratio 2.75 this is 0.96 at rho = 0.9, 0.78 at 0.95 and 0.55 at 0.99.
#include <cstddef>
#include <vector>

namespace mfdem::campaigns {

// r* above; infinite when |rho| >= 1 (every run should be cheap), 0 for rho = 0.
double control_variate_optimal_ratio(double correlation, double cost_ratio);

// The estimator's variance against plain sampling of the same cost, for m / n = ratio (>= 1)
// and cost_ratio = w_hi / w_lo.
double control_variate_variance_ratio(double correlation, double cost_ratio, double ratio);

struct ControlVariateEstimate {
  std::size_t n = 0, m = 0;          // reference runs (paired); cheap runs (paired and extra)
  double estimate = 0.0;             // E above
  double plain_mean = 0.0;           // mean_n(hi): the reference runs alone
  double cheap_mean_paired = 0.0, cheap_mean_all = 0.0;  // mean_n(lo), mean_m(lo)
  double alpha = 0.0;                // cov(hi, lo) / var(lo), from the paired runs
  double correlation = 0.0;          // rho of the paired runs
  double sd_reference = 0.0, sd_cheap = 0.0;  // sample standard deviations (paired runs; all cheap runs)
  double variance = 0.0;             // var(E) above, from the sample moments
  double plain_variance = 0.0;       // var(hi) / n
  double half_width = 0.0;           // 95 % interval of E: t_{0.975, n-2} sqrt(var(E))
  double plain_half_width = 0.0;     // 95 % Student-t interval of mean_n(hi)
  double cost_ratio = 0.0;           // w_hi / w_lo (0: unknown)
  double optimal_ratio = 0.0;        // r* for the measured rho and costs
  double variance_ratio_optimal = 0.0;  // at r*, against plain sampling of the same cost
  double variance_ratio_as_run = 0.0;   // at the runs' m / n, against plain sampling of the same cost
  // The cheap runs pay at the optimal split: less variance than reference runs alone at equal cost.
  bool pays() const { return variance_ratio_optimal < 1.0; }
};

// `reference` and `cheap_paired` on the same seeds (n >= 3, in the same order), `cheap_extra` on
// seeds of their own; costs per run in any one unit (w_hi, w_lo > 0). `plain_cost` is what one
// sample of plain sampling costs (0: w_hi); it differs when a seed's own cost (its packing) is
// counted with the cheap runs, which every seed has: the variance ratios then scale by
// w_hi / plain_cost. Throws std::invalid_argument for unpaired lists, n < 3, a cheap output
// without spread, or costs <= 0.
ControlVariateEstimate control_variate_estimate(const std::vector<double>& reference,
                                                const std::vector<double>& cheap_paired,
                                                const std::vector<double>& cheap_extra, double reference_cost,
                                                double cheap_cost, double plain_cost = 0.0);

}  // namespace mfdem::campaigns
