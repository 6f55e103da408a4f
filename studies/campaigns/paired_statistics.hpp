#pragma once
// Differences of a model from the reference, paired by seed: both run on the same deposited
// bed, so the seed-to-seed scatter they share cancels in the difference.
#include <cstddef>
#include <vector>

namespace mfdem::campaigns {

// Mean of n values with the half-width of its two-sided 95 % Student-t interval,
// t_{0.975, n-1} s / sqrt(n) (s the sample standard deviation); the half-width is infinite for
// n < 2 (no spread can be estimated from one seed).
struct MeanInterval {
  double mean = 0.0;
  double half_width = 0.0;
  double standard_deviation = 0.0;
  std::size_t n = 0;

  double low() const { return mean - half_width; }
  double high() const { return mean + half_width; }
  // The interval excludes zero: the difference exceeds the seed-to-seed spread.
  bool resolved() const { return low() > 0.0 || high() < 0.0; }
};

MeanInterval mean_interval(const std::vector<double>& values);

// The plain mean of the values; 0 for none.
double mean_of(const std::vector<double>& values);

// (model - reference) / reference per seed, for the seeds where both are given.
std::vector<double> relative_differences(const std::vector<double>& model, const std::vector<double>& reference);

// How a model's paired difference stands against a tolerance (0.05 for 5 %).
enum class Verdict { within, outside, undecided };
// within: the whole 95 % interval lies inside +-tolerance; outside: wholly beyond it; else
// undecided (more seeds would tell).
Verdict verdict(const MeanInterval& difference, double tolerance);

// The number of seeds at which the interval of `difference` would decide its verdict if its mean
// and standard deviation held: the smallest n >= 2 with t_{0.975, n-1} s / sqrt(n) below the
// distance of the mean from the band edge, ||mean| - tolerance|. 0 when it cannot be said (fewer
// than 2 seeds, or the mean on the edge) or would take more than `limit` seeds.
int seeds_to_decide(const MeanInterval& difference, double tolerance, int limit = 1000);

// F of a sampled curve at u = at, linearly interpolated between the samples around it (u
// ascending), held at the first and last sample outside them.
double interpolate_curve(const std::vector<double>& u, const std::vector<double>& f, double at);

// Normalised RMS difference of two F(u) curves: the model's F, linearly interpolated at the
// reference's samples within the u both cover, against the reference's F, as
// sqrt(mean (F_m - F_r)^2) / max F_r. 0 for identical curves.
double normalised_rms_difference(const std::vector<double>& u_model, const std::vector<double>& f_model,
                                 const std::vector<double>& u_reference, const std::vector<double>& f_reference);

}  // namespace mfdem::campaigns
