#pragma once
// `mfdem optimise-layer`: the cheapest ball layer (the highest layer, or the narrowest zone of
// clumps) whose calibrated error on both outputs stays within a tolerance, and the front of speed
// against accuracy on the way.
//
// One surrogate of both outputs over (mu_r, extent) is fitted on every run made so far, so the
// calibration of mu_r at one extent starts from what its neighbours' runs taught: at a candidate
// extent, mu_r is the minimiser of the predicted misfit there, run, refitted, until it settles.
// Its calibrated error is measured, not predicted: the paired relative differences from the
// reference over the seeds at the best run. The extents are searched by bisection between the
// dearest end (few balls) and the cheapest (many), on the assumption that the calibrated error
// grows with the share of balls; every extent evaluated is on the front.
//
// A tolerance finer than the seeds can resolve is not met silently: the tolerance used is never
// below twice the standard error of the paired differences, and the result says how many seeds
// would resolve the one asked.
#include <optional>
#include <string>
#include <vector>

#include "studies/campaigns/calibrate.hpp"

namespace mfdem::campaigns {

struct OptimiseLayerRequest {
  std::string policy = "layer-by-height";
  CalibrationParameter friction{"mu_r", 0.0, 0.6};
  CalibrationParameter extent{"h_fraction", 0.3, 0.9};  // h, h_fraction or d
  std::vector<std::uint64_t> seeds = {1, 2, 3};
  Model reference_model;                 // all-clump
  bool contact_quantile = false;
  double tolerance = 0.05;               // on both relative errors
  int initial = 6;                       // the shared 2-D design over (mu_r, extent)
  int runs_per_extent = 3;               // mu_r proposals at one extent at most
  int max_extents = 6;                   // extents evaluated at most (the two ends included)
  double resolution = 0.05;              // stop when the bracket is narrower (fraction of the extent's range)
  double shortest_length = 0.1;          // the surrogate's, as in calibrate
};

// One extent with its calibrated mu_r, measured on every seed.
struct LayerCandidate {
  double extent = 0.0, rolling_friction = 0.0;
  RunOutputs mean;                       // over the seeds
  MeanInterval peak_error, contact_error;  // paired relative differences from the reference
  double speedup = 0.0;                  // reference's mean preparation + push over the model's
  double push_speedup = 0.0;             // the push alone
  double tolerance_used = 0.0;           // max(tolerance, twice the larger standard error)
  bool within = false;                   // both |mean errors| <= tolerance_used
  int runs_here = 0;                     // candidates run at this extent for the calibration of mu_r
};

struct OptimiseLayerResult {
  std::array<double, 2> targets{};
  std::vector<RunOutputs> reference_runs;  // per seed
  std::vector<LayerCandidate> front;       // one per extent evaluated, in the order evaluated
  std::vector<calibration::Evaluation> runs;  // every (mu_r, extent) run, means over the seeds
  std::optional<std::size_t> chosen;       // into front: the cheapest within tolerance
  // Twice the largest standard error of a paired difference seen on the front: the finest
  // tolerance these seeds resolve, and the seeds that would resolve the one asked.
  double resolvable_tolerance = 0.0;
  int seeds_to_resolve = 0;
  bool cheaper_when_larger = true;         // layer height: more balls as it grows; zone distance: fewer
  int dem_runs = 0;                        // of the (mu_r, extent) candidates, each on every seed
  double candidates_wall = 0.0;            // s, their preparations and pushes
  double reference_wall = 0.0;             // s, one reference run's on average
  double cost_in_reference_runs() const { return reference_wall > 0.0 ? candidates_wall / reference_wall : 0.0; }
};

OptimiseLayerResult optimise_layer(CandidateRunner& runner, const OptimiseLayerRequest& request);

// A model's runs against the reference's on the same seeds (in the same order): paired errors,
// speedups and the verdict at `tolerance` (never below twice the errors' standard error). The
// extent and mu_r are left to the caller.
LayerCandidate measure_candidate(const std::vector<RunOutputs>& per_seed, const std::vector<RunOutputs>& reference,
                                 double tolerance);

// One family's search (a policy and its extent), and models measured as they are (uncalibrated)
// on the same seeds for scale: what `mfdem optimise-layer` reports and draws.
struct FamilyFront {
  std::string policy;        // layer-by-height or zone-by-distance
  std::string extent_name;   // h, h_fraction or d
  OptimiseLayerResult result;
};
struct MeasuredModel {
  std::string model;         // its text
  LayerCandidate measured;
};

}  // namespace mfdem::campaigns
