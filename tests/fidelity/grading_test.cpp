// Stone sizes from a sieve curve: the sampler reproduces the curve, and each stone's draw depends
// only on the seed and the stone's index.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "fidelity/grading.hpp"

using namespace mfdem::fidelity;
using mfdem::dem::Mat3;

namespace {

constexpr int samples = 20000;
constexpr int templates = 12;
// Kolmogorov-Smirnov: P(sqrt(n) D_n > 1.949) = 0.001 for n this large (Kolmogorov distribution).
constexpr double ks_critical = 1.949;

// sup |F_n - F| over the sample, both sides of each step.
template <class Cdf>
double ks_distance(std::vector<double> sample, Cdf cdf) {
  std::sort(sample.begin(), sample.end());
  const double n = static_cast<double>(sample.size());
  double d = 0.0;
  for (std::size_t i = 0; i < sample.size(); ++i) {
    const double f = cdf(sample[i]);
    d = std::max({d, std::abs((i + 1) / n - f), std::abs(i / n - f)});
  }
  return d;
}

std::vector<double> sizes_mm(const StoneSampler& sampler) {
  std::vector<double> sizes;
  for (int k = 0; k < samples; ++k) sizes.push_back(sampler.draw(k).size * 1000.0);
  return sizes;
}

}  // namespace

TEST_CASE("the default curve is the mid-line of the EN 13450 31.5/63 envelope", "[fidelity][grading]") {
  const SieveCurve curve = SieveCurve::en13450_31_5_63();
  const std::vector<std::pair<double, double>> expected{{22.4, 1.5}, {31.5, 13}, {40, 47.5}, {50, 84.5}, {63, 98.5}, {80, 100}};
  REQUIRE(curve.points().size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CHECK(curve.points()[i].size_mm == expected[i].first);
    CHECK(curve.points()[i].passing_percent == expected[i].second);
  }
  CHECK(curve.fines_fraction() == Approx(0.015));
  // Renormalised: (47.5 - 1.5) / 98.5 of the modelled mass is finer than 40 mm.
  CHECK(curve.mass_fraction_below(40.0) == Approx(46.0 / 98.5).epsilon(1e-14));
  CHECK(curve.size_at_mass_fraction(46.0 / 98.5) == Approx(40.0).epsilon(1e-12));
  CHECK(curve.size_at_count_fraction(curve.count_fraction_below(47.0)) == Approx(47.0).epsilon(1e-12));
}

TEST_CASE("sizes drawn by mass reproduce the sieve curve (KS on 20,000 stones)", "[fidelity][grading]") {
  const StoneSampler sampler(2024, templates);
  const std::vector<double> sizes = sizes_mm(sampler);
  const SieveCurve& curve = sampler.curve();
  // The number of stones follows the count distribution implied by the curve: exact KS test.
  const double d = ks_distance(sizes, [&](double x) { return curve.count_fraction_below(x); });
  CHECK(std::sqrt(double(samples)) * d < ks_critical);
  // And their mass (d^3 for a given template) follows the curve itself at every sieve. The
  // weighted estimate has standard error sqrt(F (1 - F) / n_eff) <= 0.5 / sqrt(n_eff), with
  // n_eff = (sum w)^2 / sum w^2 for weights w = d^3; four standard errors.
  double total = 0.0, total2 = 0.0;
  for (double s : sizes) total += s * s * s, total2 += std::pow(s, 6);
  const double tolerance = 4.0 * 0.5 / std::sqrt(total * total / total2);
  for (const auto& sieve : curve.points()) {
    double passing = 0.0;
    for (double s : sizes) passing += s < sieve.size_mm ? s * s * s : 0.0;
    CAPTURE(sieve.size_mm);
    CHECK(std::abs(passing / total - curve.mass_fraction_below(sieve.size_mm)) < tolerance);
  }
  CHECK(*std::min_element(sizes.begin(), sizes.end()) >= curve.smallest_mm());
  CHECK(*std::max_element(sizes.begin(), sizes.end()) <= curve.largest_mm());
}

TEST_CASE("sizes drawn by count follow the curve as a count distribution (KS)", "[fidelity][grading]") {
  const SieveCurve user({{20, 0}, {30, 20}, {40, 70}, {50, 100}});
  const StoneSampler sampler(7, templates, user, SizeWeighting::by_count);
  const double d = ks_distance(sizes_mm(sampler), [&](double x) { return user.mass_fraction_below(x); });
  CHECK(std::sqrt(double(samples)) * d < ks_critical);
}

TEST_CASE("one seed gives each stone the same template, size and orientation, in any order", "[fidelity][grading]") {
  const StoneSampler a(99, templates), b(99, templates), c(100, templates);
  std::vector<StoneDraw> forward;
  for (int k = 0; k < 100; ++k) forward.push_back(a.draw(k));
  for (int k = 99; k >= 0; --k) {  // backwards, on another sampler
    const StoneDraw again = b.draw(k);
    CHECK(again.template_index == forward[k].template_index);
    CHECK(again.size == forward[k].size);
    CHECK(again.orientation.coeffs() == forward[k].orientation.coeffs());
  }
  int same = 0;
  for (int k = 0; k < 100; ++k) same += c.draw(k).size == forward[k].size;
  CHECK(same == 0);
  // The sizes do not depend on the curve's use by another fidelity: a ball and a clump of stone k
  // come from the same draw (the sampler knows nothing of fidelity); the stream seeds of one
  // packing are all different.
  std::set<unsigned long> seeds;
  for (int k = 0; k < 200000; ++k) seeds.insert(StoneSampler::stream_seed(99, k));
  CHECK(seeds.size() == 200000);
  CHECK(*seeds.begin() >= 1);
}

TEST_CASE("templates and orientations are drawn uniformly", "[fidelity][grading]") {
  const StoneSampler sampler(5, templates);
  std::vector<int> count(templates, 0);
  Mat3 mean_rotation = Mat3::Zero();
  double worst_norm = 0.0;
  for (int k = 0; k < samples; ++k) {
    const StoneDraw draw = sampler.draw(k);
    ++count[draw.template_index];
    worst_norm = std::max(worst_norm, std::abs(draw.orientation.norm() - 1.0));
    mean_rotation += draw.orientation.toRotationMatrix();
  }
  CHECK(worst_norm < 1e-12);
  mean_rotation /= samples;
  // Binomial counts: n p (1 - p) variance, five standard deviations.
  const double p = 1.0 / templates;
  for (int c : count) CHECK(std::abs(c - samples * p) < 5.0 * std::sqrt(samples * p * (1 - p)));
  // Entries of a uniformly random rotation have mean 0 and variance 1/3: five standard errors.
  CHECK(mean_rotation.cwiseAbs().maxCoeff() < 5.0 * std::sqrt(1.0 / 3.0 / samples));
}

TEST_CASE("a malformed sieve curve is refused with what is wrong", "[fidelity][grading]") {
  CHECK_THROWS_WITH(SieveCurve({{40, 100}}), "sieve curve: needs at least two sieves (got 1)");
  CHECK_THROWS_WITH(SieveCurve({{40, 10}, {31.5, 100}}), "sieve curve: sieve sizes must increase (31.5 mm follows 40 mm)");
  CHECK_THROWS_WITH(SieveCurve({{30, 50}, {40, 20}, {50, 100}}), Catch::Contains("must not decrease"));
  CHECK_THROWS_WITH(SieveCurve({{30, 0}, {40, 90}}), "sieve curve: the largest sieve (40 mm) must pass 100 % (got 90 %)");
  CHECK_THROWS_WITH(SieveCurve({{30, 0}, {40, 120}}), Catch::Contains("must be between 0 and 100"));
  CHECK_THROWS_WITH(StoneSampler(1, 0), Catch::Contains("no template"));
}
