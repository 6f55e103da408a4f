#include "fidelity/grading.hpp"

#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

namespace mfdem::fidelity {

namespace {

constexpr double mm = 1e-3;  // m per mm
constexpr std::uint32_t mask31 = 0x7fffffffu;

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// A bijection of [0, 2^31): xor-shifts and odd multipliers modulo 2^31 are each invertible.
std::uint32_t mix31(std::uint32_t x) {
  x ^= x >> 16;
  x = (x * 0x7feb352du) & mask31;
  x ^= x >> 15;
  x = (x * 0x846ca68bu) & mask31;
  x ^= x >> 16;
  return x;
}

}  // namespace

SieveCurve::SieveCurve(std::vector<SievePoint> points) : points_(std::move(points)) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("sieve curve: " + what); };
  if (points_.size() < 2) fail(fmt::format("needs at least two sieves (got {})", points_.size()));
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const auto& p = points_[i];
    if (!(p.size_mm > 0.0) || !std::isfinite(p.size_mm)) fail(fmt::format("sieve size {} mm must be positive", p.size_mm));
    if (!(p.passing_percent >= 0.0 && p.passing_percent <= 100.0))
      fail(fmt::format("passing {} % at {} mm must be between 0 and 100", p.passing_percent, p.size_mm));
    if (i > 0 && !(p.size_mm > points_[i - 1].size_mm))
      fail(fmt::format("sieve sizes must increase ({} mm follows {} mm)", p.size_mm, points_[i - 1].size_mm));
    if (i > 0 && p.passing_percent < points_[i - 1].passing_percent)
      fail(fmt::format("passing percentages must not decrease with size ({} % at {} mm after {} % at {} mm)",
                       p.passing_percent, p.size_mm, points_[i - 1].passing_percent, points_[i - 1].size_mm));
  }
  if (points_.back().passing_percent != 100.0)
    fail(fmt::format("the largest sieve ({} mm) must pass 100 % (got {} %)", points_.back().size_mm,
                     points_.back().passing_percent));
  if (points_.front().passing_percent == 100.0)
    fail(fmt::format("everything passes the smallest sieve ({} mm): no stone is coarser", points_.front().size_mm));
  // Number of stones per interval: integral of c / d^3, c = mass density dP/dd of the interval.
  count_cumulative_.assign(points_.size(), 0.0);
  for (std::size_t i = 1; i < points_.size(); ++i) {
    const double a = points_[i - 1].size_mm, b = points_[i].size_mm;
    const double c = (points_[i].passing_percent - points_[i - 1].passing_percent) / (b - a);
    count_cumulative_[i] = count_cumulative_[i - 1] + c * (1.0 / (a * a) - 1.0 / (b * b)) / 2.0;
  }
}

SieveCurve SieveCurve::en13450_31_5_63() {
  // Mid-line of the envelope (see grading.hpp): (lower + upper) / 2 at each sieve.
  return SieveCurve({{22.4, (0.0 + 3.0) / 2.0},
                     {31.5, (1.0 + 25.0) / 2.0},
                     {40.0, (30.0 + 65.0) / 2.0},
                     {50.0, (70.0 + 99.0) / 2.0},
                     {63.0, (97.0 + 100.0) / 2.0},
                     {80.0, 100.0}});
}

double SieveCurve::mass_fraction_below(double size_mm) const {
  if (size_mm <= smallest_mm()) return 0.0;
  if (size_mm >= largest_mm()) return 1.0;
  const auto upper = std::upper_bound(points_.begin(), points_.end(), size_mm,
                                      [](double d, const SievePoint& p) { return d < p.size_mm; });
  const auto lower = upper - 1;
  const double t = (size_mm - lower->size_mm) / (upper->size_mm - lower->size_mm);
  const double passing = lower->passing_percent + t * (upper->passing_percent - lower->passing_percent);
  const double p0 = points_.front().passing_percent;
  return (passing - p0) / (100.0 - p0);
}

double SieveCurve::count_fraction_below(double size_mm) const {
  if (size_mm <= smallest_mm()) return 0.0;
  if (size_mm >= largest_mm()) return 1.0;
  const std::size_t i = std::upper_bound(points_.begin(), points_.end(), size_mm,
                                         [](double d, const SievePoint& p) { return d < p.size_mm; }) -
                        points_.begin();
  const double a = points_[i - 1].size_mm, b = points_[i].size_mm;
  const double c = (points_[i].passing_percent - points_[i - 1].passing_percent) / (b - a);
  const double partial = c * (1.0 / (a * a) - 1.0 / (size_mm * size_mm)) / 2.0;
  return (count_cumulative_[i - 1] + partial) / count_cumulative_.back();
}

double SieveCurve::size_at_mass_fraction(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  const double p0 = points_.front().passing_percent;
  const double target = p0 + u * (100.0 - p0);
  for (std::size_t i = 1; i < points_.size(); ++i) {
    const auto& lo = points_[i - 1];
    const auto& hi = points_[i];
    if (target <= hi.passing_percent && hi.passing_percent > lo.passing_percent)
      return lo.size_mm + (target - lo.passing_percent) / (hi.passing_percent - lo.passing_percent) * (hi.size_mm - lo.size_mm);
  }
  return largest_mm();
}

double SieveCurve::size_at_count_fraction(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  const double target = u * count_cumulative_.back();
  for (std::size_t i = 1; i < points_.size(); ++i) {
    if (target > count_cumulative_[i] || count_cumulative_[i] == count_cumulative_[i - 1]) continue;
    const double a = points_[i - 1].size_mm, b = points_[i].size_mm;
    const double c = (points_[i].passing_percent - points_[i - 1].passing_percent) / (b - a);
    const double inverse_square = 1.0 / (a * a) - 2.0 * (target - count_cumulative_[i - 1]) / c;
    return std::clamp(1.0 / std::sqrt(inverse_square), a, b);
  }
  return largest_mm();
}

StoneSampler::StoneSampler(std::uint64_t seed, int template_count, SieveCurve curve, SizeWeighting weighting)
    : seed_(seed), template_count_(template_count), curve_(std::move(curve)), weighting_(weighting) {
  if (template_count < 1) throw std::invalid_argument("stone sampler: the shape library has no template");
}

unsigned long StoneSampler::stream_seed(std::uint64_t seed, std::int64_t stone) {
  if (stone < 0 || stone > mask31)
    throw std::out_of_range(fmt::format("stone index {} is outside [0, 2^31)", stone));
  const auto key = static_cast<std::uint32_t>(splitmix64(seed)) & mask31;
  // +1: GSL's mt19937 replaces seed 0 by its default seed, which another stone could have.
  return static_cast<unsigned long>(mix31(static_cast<std::uint32_t>(stone) ^ key)) + 1UL;
}

StoneDraw StoneSampler::draw(std::int64_t stone) const {
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), &gsl_rng_free);
  gsl_rng_set(rng.get(), stream_seed(seed_, stone));
  StoneDraw draw;
  draw.template_index = static_cast<int>(gsl_rng_uniform_int(rng.get(), static_cast<unsigned long>(template_count_)));
  const double u = gsl_rng_uniform_pos(rng.get());
  draw.size = mm * (weighting_ == SizeWeighting::by_mass ? curve_.size_at_count_fraction(u) : curve_.size_at_mass_fraction(u));
  const double u1 = gsl_rng_uniform(rng.get());
  const double u2 = gsl_rng_uniform(rng.get());
  const double u3 = gsl_rng_uniform(rng.get());
  const double two_pi = 2.0 * std::numbers::pi;
  draw.orientation = dem::Quat(std::sqrt(u1) * std::cos(two_pi * u3), std::sqrt(1.0 - u1) * std::sin(two_pi * u2),
                               std::sqrt(1.0 - u1) * std::cos(two_pi * u2), std::sqrt(u1) * std::sin(two_pi * u3));
  return draw;
}

}  // namespace mfdem::fidelity
