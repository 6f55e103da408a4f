#pragma once
// The numbers behind `mfdem compare`'s figures, computed here and written to OUT/figures.h5; the
// Python module (studies/python/mfdem/compare_figures.py) only draws them:
//   /                     attrs config (its name), seeds (how many the study asked), tolerance
//   /curves/NN            one model (NN its place in --models): attrs model, seeds;
//                         u, mean, low, high: F(u) on a common grid of u, the mean over the seeds
//                         and the lowest and highest seed at each u (m, N)
//   /section              attrs seed, slab_half_width, x_min, x_max, z_min, z_max,
//                         displacement_clip, clip_percentile, chain_threshold, largest_chain_force,
//                         chain_clip (the clip_percentile of the chains drawn, over every model),
//                         sleeper_x0, sleeper_x1, sleeper_z0, sleeper_z1 (the sleeper at u_end)
//   /section/NN           one model's view of the same seed: attrs model;
//                         x, z, radius, displacement, dx, dz: the stones whose centre lies in the
//                         slab |y - y_sleeper| <= slab_half_width (m; displacement over the push);
//                         x1, z1, x2, z2, force: the stone-stone contacts in the slab carrying at
//                         least chain_threshold, as lines between the stones' centres (m, N)
// The speedup-against-error figure reads compare.csv.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "studies/campaigns/compare.hpp"
#include "studies/railway/push_output.hpp"

namespace mfdem::campaigns {

struct CurveBand {
  std::string model;
  std::size_t seeds = 0;
  std::vector<double> u, mean, low, high;
};

// The seeds' F(u) curves of one model on `points` values of u from 0 to the shortest curve's
// last u: their mean and their pointwise lowest and highest. No curve: an empty band.
CurveBand curve_band(const std::string& model, const std::vector<railway::ForceCurve>& curves,
                     std::size_t points = 250);

struct SectionView {
  std::string model;
  std::vector<double> x, z, radius, displacement, dx, dz;  // stones in the slab
  std::vector<double> x1, z1, x2, z2, force;              // chains in the slab
};

struct Sections {
  std::uint64_t seed = 0;
  double slab_half_width = 0.0;                 // m
  double x_min = 0.0, x_max = 0.0, z_min = 0.0, z_max = 0.0;  // the region drawn, m
  double clip_percentile = 0.98;
  double displacement_clip = 0.0;               // m: the percentile over every model's slab stones
  double chain_threshold = 0.0;                 // N: the reference's mean stone-stone contact force
  double largest_chain_force = 0.0;             // N: over every model
  double chain_clip = 0.0;                      // N: the percentile of the chains drawn, over every model
  double sleeper_x0 = 0.0, sleeper_x1 = 0.0, sleeper_z0 = 0.0, sleeper_z1 = 0.0;  // at u_end
  std::vector<SectionView> models;
};

// One finished run's outputs for the section views.
struct RunFiles {
  std::string model;
  std::filesystem::path push, packing;  // push.h5, and the run's own packing.h5
};

// The vertical section through the sleeper's centre across the track (x-z), for every model of
// one seed: the slab holds the stones whose centres lie within half the largest stone size of
// the plane (the stones the plane cuts); the region drawn runs from 0.1 m behind the sleeper's
// trailing end to the bed's toe ahead of its leading end, and from the floor to 0.05 m above the
// sleeper (the part of the bed the push moves). The first run is the reference, whose mean
// contact force sets the chains' threshold. Throws std::runtime_error naming a file it cannot read.
Sections section_views(std::uint64_t seed, const std::vector<RunFiles>& runs);

// Writes the layout above to `path` (through a temporary file and a rename).
struct FigureLabels {
  std::string config;
  std::size_t seeds = 0;
  double tolerance = 0.05;  // the verdict's, relative
};
void write_figure_data(const std::filesystem::path& path, const FigureLabels& labels,
                       const std::vector<CurveBand>& curves, const Sections& sections);

// The figure data of a compare study from its store: every model's band over its finished seeds,
// and the section views of the first seed the reference finished (the models finished on it).
// Returns false, writing nothing, when the reference has no finished run.
bool write_compare_figure_data(const std::filesystem::path& path, const runs::RunStore& store,
                               const CompareRequest& request);

// The same data for pushes outside a store (`mfdem plot`): each run its own curve (one seed), the
// first run the reference of the sections; `seed` names the runs' seed in the section's title.
void write_push_figure_data(const std::filesystem::path& path, const std::string& title, std::uint64_t seed,
                            const std::vector<RunFiles>& runs);

}  // namespace mfdem::campaigns
