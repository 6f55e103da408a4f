#pragma once
// What N packings (seeds) of one model say about one of its outputs: the mean with its 95 %
// Student-t interval, the standard deviation, a bootstrap interval that assumes no normality, the
// running mean with its band as seeds were added, and how many seeds an interval of a requested
// width needs.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "studies/campaigns/paired_statistics.hpp"

namespace mfdem::campaigns {

// The percentile bootstrap of the mean (Efron & Tibshirani 1993, ch. 13): `resamples` resamples
// of the values drawn with replacement (GSL's MT19937 seeded with `seed`, so the interval is
// reproducible), the interval between their means' (1 - level)/2 and (1 + level)/2 quantiles.
struct BootstrapSettings {
  std::size_t resamples = 10000;
  std::uint64_t seed = 1;
  double level = 0.95;
};
struct Interval {
  double low = 0.0, high = 0.0;
};
// Throws std::invalid_argument for fewer than 2 values.
Interval bootstrap_mean_interval(const std::vector<double>& values, const BootstrapSettings& settings);

// The fewest seeds n >= 2 whose 95 % Student-t half-width, t_{0.975, n-1} s / sqrt(n), is at
// most relative_half_width x |mean|, for the standard deviation s and mean measured so far. Nothing
// for fewer than 2 values or a zero mean; at most `cap` (returned when even cap is not enough).
std::optional<std::size_t> seeds_for_relative_half_width(const MeanInterval& so_far, double relative_half_width,
                                                          std::size_t cap = 1000000);

struct OutputSummary {
  MeanInterval mean;                 // mean, 95 % Student-t half-width, standard deviation, n
  std::optional<Interval> bootstrap; // 95 % percentile bootstrap of the mean (n >= 2)
  std::vector<MeanInterval> running; // after the first 1, 2, ..., n values, in their order
  double requested_width = 0.0;      // relative half-width asked for (0: none)
  std::optional<std::size_t> seeds_for_width;  // seeds that width needs, from the spread so far
  // The coefficient of variation s / |mean| (the scatter between packings), 0 without spread.
  double variation() const { return mean.mean != 0.0 && mean.n > 1 ? mean.standard_deviation / std::abs(mean.mean) : 0.0; }
  // The 95 % t half-width relative to |mean|.
  double relative_half_width() const { return mean.mean != 0.0 ? mean.half_width / std::abs(mean.mean) : 0.0; }
};

// Values in the order the seeds were run (the running mean follows that order).
OutputSummary summarise_output(const std::vector<double>& values, const BootstrapSettings& bootstrap,
                               double requested_relative_half_width = 0.0);

}  // namespace mfdem::campaigns
