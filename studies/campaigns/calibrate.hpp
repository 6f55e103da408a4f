#pragma once
// `mfdem calibrate`: the ball layer's parameters (its rolling friction mu_r, the layer height h or
// zone distance d, optionally the balls' friction) fitted so that the multi-layer model's peak
// lateral force and maximum contact force match the all-clump reference, with the calibration
// loop of calibration/ (surrogates, expected improvement, posterior) over DEM runs in the store.
//
// A candidate is the policy with its parameters; it is run on the same seeds as every other
// candidate (paired, so the packings' scatter cancels in the comparison) and its outputs are the
// means over those seeds. The reference is the all-clump model on the same seeds (or numbers the
// user gives). The saving is bounded by the parameters' ranges: the lowest layer height (the
// largest zone distance) a candidate may take still turns stones into balls; a range that
// allows no ball, or lies outside the bed, is refused.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "calibration/calibration_loop.hpp"
#include "calibration/posterior.hpp"
#include "studies/campaigns/paired_statistics.hpp"
#include "studies/campaigns/push_runs.hpp"

namespace mfdem::campaigns {

struct CalibrationParameter {
  std::string name;  // mu_r, ball_mu, or a parameter of the policy (h, h_fraction, d)
  double lower = 0.0, upper = 0.0;
};

// "mu_r=0:0.6,h_fraction=0.3:0.9" for `policy`; throws config::ConfigError naming `option` (or
// `policy_option` for a policy without a ball layer) and the value for a malformed entry, an unknown name, an empty range, or a range that lets no stone be a
// ball or lies outside the bed of `config`.
std::vector<CalibrationParameter> parse_calibration_parameters(const std::string& text, const std::string& policy,
                                                               const railway::PushStudyConfig& config,
                                                               const std::string& option,
                                                               const std::string& policy_option = "--policy");

// The model of a candidate: the policy with the parameters' values written in.
Model candidate_model(const std::string& policy, const std::vector<CalibrationParameter>& parameters,
                      const Eigen::VectorXd& values);

// The two outputs a calibration matches, of one run.
struct RunOutputs {
  double peak_force = 0.0;     // N
  double contact_force = 0.0;  // N: the maximum, or its 99.9 % quantile
  double push_wall = 0.0;      // s, the push alone
  double wall = 0.0;           // s, the model's preparation (from the shared deposition) and push
};

// The means over runs (of one model on several seeds) of every field.
RunOutputs mean_outputs(const std::vector<RunOutputs>& runs);

// Where the runs come from: DEM pushes in the store (PushRunner), or a stand-in in tests.
class CandidateRunner {
 public:
  virtual ~CandidateRunner() = default;
  // The run of `model` on `seed` at a level, found in the store or computed there; throws
  // std::runtime_error naming the run when it failed.
  virtual RunOutputs run(const Model& model, std::uint64_t seed, calibration::Level level) = 0;
};

// DEM pushes: the expensive level on `config`, the cheap one on `cheap_config`, or without one on
// `config` too (a cheap level of fewer seeds).
class PushRunner final : public CandidateRunner {
 public:
  PushRunner(runs::RunStore& store, railway::PushStudyConfig config, std::optional<railway::PushStudyConfig> cheap,
             RunContext context, bool contact_quantile);
  RunOutputs run(const Model& model, std::uint64_t seed, calibration::Level level) override;

 private:
  runs::RunStore& store_;
  railway::PushStudyConfig config_;
  std::optional<railway::PushStudyConfig> cheap_;
  RunContext context_;
  bool contact_quantile_;
};

struct CalibrateRequest {
  std::string policy = "layer-by-height";
  std::vector<CalibrationParameter> parameters;
  std::vector<std::uint64_t> seeds = {1, 2, 3};   // every candidate runs on all of them
  std::vector<std::uint64_t> verify_seeds;        // fresh seeds for the check at the calibrated point
  std::optional<std::array<double, 2>> reference; // peak and contact force in N; else runs of reference_model
  // The model matched: all-clump, or (a synthetic truth, to test a calibration) a multi-layer model
  // at known parameters.
  Model reference_model;
  bool contact_quantile = false;                  // match the 99.9 % quantile of the contact force, not its maximum
  double budget = 20.0;                           // candidates (expensive-level ones; a cheap one costs cheap_cost)
  int initial_expensive = 0;                      // the initial design's expensive candidates; 0: 2 d + 2
  int initial_cheap = 0;                          // and cheap ones (two levels); 0: 3 x the expensive ones
  int batch = 1;
  bool two_levels = false;
  double cheap_cost = 0.25;
  // The cheap level's seeds (empty: `seeds`). Fewer seeds on the same config is a cheap level by
  // itself; the runs it shares with the expensive level are then one run, counted once.
  std::vector<std::uint64_t> cheap_seeds;
  bool cheap_on_same_config = false;
  // The seeds a candidate runs on at a level.
  const std::vector<std::uint64_t>& seeds_at(calibration::Level level) const {
    return level == calibration::Level::cheap && !cheap_seeds.empty() ? cheap_seeds : seeds;
  }
  std::uint64_t design_seed = 1;
  double stop_improvement = 1e-5;
  // The surrogates' shortest length scale, as a fraction of each parameter's range: DEM outputs
  // scatter between runs, and a process allowed shorter scales reads that scatter as structure.
  double shortest_length = 0.1;
  std::filesystem::path record;                   // the loop's record (OUT/calibration_record.csv)
};

struct VerificationRow {
  std::uint64_t seed = 0;
  RunOutputs model, reference;
};

struct CalibrateResult {
  std::array<double, 2> targets{};         // N
  std::array<double, 2> target_sd{};       // N, of the reference's mean over seeds (0 when given)
  std::vector<RunOutputs> reference_runs;  // per seed (empty when given)
  calibration::LoopResult loop;
  std::optional<calibration::MisfitSurrogate> surrogate;  // fitted on every candidate
  calibration::PosteriorSummary posterior;
  Eigen::VectorXd calibrated;              // the minimiser of the predicted misfit
  std::array<calibration::Prediction, 2> predicted{};  // the outputs there
  std::vector<VerificationRow> verification;
  MeanInterval peak_difference, contact_difference;    // paired, relative, on the fresh seeds
  int dem_runs = 0;            // of the candidates (each on every seed), not counting the reference's
  double candidates_wall = 0.0;  // s, their preparations and pushes as the records give them
  double reference_wall = 0.0;  // s, mean preparation and push of the all-clump runs (reference or verification), 0 if none
  // The calibration's cost in reference-run equivalents: candidates_wall / reference_wall.
  double cost_in_reference_runs() const { return reference_wall > 0.0 ? candidates_wall / reference_wall : 0.0; }
};

CalibrateResult run_calibration(CandidateRunner& runner, const CalibrateRequest& request);

// The calibrated parameters' values in the reference model, when it is a model of the same policy
// that sets them all (a synthetic truth); nothing for the all-clump reference.
std::optional<Eigen::VectorXd> reference_parameters(const CalibrateRequest& request);

}  // namespace mfdem::campaigns
