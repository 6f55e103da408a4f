#pragma once
// Stone sizes from a sieve curve, and the per-stone draws that make a packing reproducible.
//
// A sieve curve gives, for each sieve size (square aperture, mm), the percentage by mass of the
// material that passes it. Between sieves the passing percentage is interpolated linearly in size.
// The material finer than the smallest sieve (its passing percentage) is not modelled: the curve
// is renormalised to run from 0 at the smallest sieve to 100 % at the last one, which must be
// 100 %. A stone's size d is its intermediate dimension, what a sieve measures (ClumpTemplate).
//
// Default: EN 13450 railway ballast 31.5/63, the mid-line of the grading envelope:
//   sieve (mm)      22.4   31.5   40     50     63     80
//   passing (%)     0-3    1-25   30-65  70-99  97-100 100      (envelope)
//   mid-line (%)    1.5    13     47.5   84.5   98.5   100
// The envelope of EN 13450 "Aggregates for railway ballast" (CEN 2002, Table 2, and its 2013
// revision) for 31.5/63 ballast, as recalled and NOT verified against the text: the standard is
// not freely available. Its grading categories differ in the upper rows (63 mm: 100 or 97-100 %,
// 50 mm: 70-99 or 65-99 %). Check against your copy, or give your own curve.
//
// A user curve is a list of (size_mm, passing_percent) pairs, e.g. in a TOML config
//   grading = [[22.4, 0], [31.5, 10], [40, 45], [50, 85], [63, 100]]
//
// Sizes by mass or by count. A sieve curve is by mass (EN 933-1). Drawing each stone's size from
// the curve's inverse directly (by_count) makes the number of stones follow it, which puts too
// much mass in the large sizes. by_mass (the default) draws sizes with the number density
//   n(d) proportional to (dP/dd) / d^3,
// so that the stones' mass, proportional to d^3 for a given template, follows the curve.
#include <cstdint>
#include <vector>

#include "dem/types.hpp"

namespace mfdem::fidelity {

struct SievePoint {
  double size_mm = 0.0;
  double passing_percent = 0.0;
};

class SieveCurve {
 public:
  // Throws std::invalid_argument saying what is wrong: fewer than two sieves, sizes not positive
  // and increasing, passing percentages outside [0, 100] or decreasing, a last sieve below 100 %,
  // or nothing coarser than the smallest sieve.
  explicit SieveCurve(std::vector<SievePoint> points);
  // The mid-line of the EN 13450 31.5/63 envelope (table above).
  static SieveCurve en13450_31_5_63();

  const std::vector<SievePoint>& points() const { return points_; }
  double smallest_mm() const { return points_.front().size_mm; }
  double largest_mm() const { return points_.back().size_mm; }
  // Mass fraction finer than the smallest sieve, which is not modelled.
  double fines_fraction() const { return points_.front().passing_percent / 100.0; }

  // Fraction of the modelled mass in stones smaller than d (0 below the smallest sieve, 1 above
  // the largest): the renormalised curve.
  double mass_fraction_below(double size_mm) const;
  // Fraction of the number of stones smaller than d when their mass follows the curve.
  double count_fraction_below(double size_mm) const;
  // Inverse functions, u in [0, 1].
  double size_at_mass_fraction(double u) const;
  double size_at_count_fraction(double u) const;

 private:
  std::vector<SievePoint> points_;
  std::vector<double> count_cumulative_;  // number of stones below each sieve, unnormalised
};

enum class SizeWeighting { by_mass, by_count };

// One stone of a packing: which template, how large, how turned.
struct StoneDraw {
  int template_index = 0;
  double size = 0.0;                          // sieve size d, metres
  dem::Quat orientation = dem::Quat::Identity();  // body frame to world, uniform over rotations
};

// Draws stone k from its own GSL mt19937 stream, seeded from (seed, k) only. Stone k is the same
// whatever else is drawn, in any order, on any thread, and whatever fidelity is chosen for it
// later: a clump and its equal-volume ball come from the same draw. The stream seed is a
// bijective mix of k with the seed, so the stones of one packing never share a stream (GSL
// seeds are 32-bit: hashed seeds would collide among ~10^5 stones).
// Draw order within a stream: template (gsl_rng_uniform_int), size (gsl_rng_uniform_pos through
// the inverse curve), orientation (three gsl_rng_uniform, Shoemake 1992, "Uniform random
// rotations", Graphics Gems III, 124-132).
class StoneSampler {
 public:
  StoneSampler(std::uint64_t seed, int template_count, SieveCurve curve = SieveCurve::en13450_31_5_63(),
               SizeWeighting weighting = SizeWeighting::by_mass);

  StoneDraw draw(std::int64_t stone) const;  // stone in [0, 2^31)
  const SieveCurve& curve() const { return curve_; }

  // The GSL seed of stone k's stream: in [1, 2^31], distinct for distinct k under one seed.
  static unsigned long stream_seed(std::uint64_t seed, std::int64_t stone);

 private:
  std::uint64_t seed_;
  int template_count_;
  SieveCurve curve_;
  SizeWeighting weighting_;
};

}  // namespace mfdem::fidelity
