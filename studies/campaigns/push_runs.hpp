#pragma once
// Push runs in the run store: the one way every multi-run study (compare, statistics,
// calibration) computes or finds the push of a model on a seed's bed.
//
// Every model of a seed starts from the same deposited bed, kept in the store
// (shared/deposit-HASH-sSEED/checkpoint.h5, made once by `mfdem pack --stop-after deposit`);
// the model's own bed is prepared from it (the policy converts the deposited clumps, the balls
// grow into place, the later stages run: bed_preparation.hpp; kept as shared/bed-sSEED-MODEL-HASH,
// so runs that differ only in their push share it) and the sleeper is pushed.
// So models differ only in fidelity and their differences are paired by seed.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "studies/railway/push_config.hpp"
#include "studies/runs/run_store.hpp"

namespace mfdem::campaigns {

// A model: a fidelity policy with its parameters and the balls' material.
struct Model {
  std::string policy = "all-clump";  // NAME[:k=v,...] (fidelity/policy.hpp)
  std::optional<double> rolling_friction, ball_friction;  // default: the config's [fidelity]

  // The policy in its normal form with the balls' material when it has balls:
  // "layer-by-height:h_fraction=0.5 mu_r=0.3".
  std::string text(const railway::PushStudyConfig& config) const;
};

// Parses "NAME[:k=v,...][@mu_r]" lists as --models gives them: models separated by ';' or by a
// ',' that starts a known policy name. Checks every policy name and parameter name against the
// registry; throws config::ConfigError naming `option` and the value.
std::vector<Model> parse_models(const std::string& list, const std::string& option);
// One model, as parse_models reads it; refuses a list of several, naming `option`.
Model parse_model(const std::string& text, const std::string& option);

// The config with the model's [fidelity] written in.
railway::PushStudyConfig with_model(const railway::PushStudyConfig& config, const Model& model);

// What the config says, in one form: its TOML table without `name` (a label) and `seed` (a run
// has its own), serialised by toml++ (keys sorted, numbers in their shortest form). Comments,
// layout, key order and how a number is typed (1e-3, 0.001) do not change it.
std::string canonical_config_text(const railway::PushStudyConfig& config);

// The run's key: seed, a readable form of the model, and a hash of everything that determines
// the run (the canonical config text, the model, the seed). ensure_push_run moves a run found
// under the key's earlier form (a hash of the config's text as written) to this one.
std::string run_key(const railway::PushStudyConfig& config, const Model& model, std::uint64_t seed);

// The store's key of the deposited bed a run of `config` on `seed` starts from (shared/KEY): a
// hash of the config without what acts after the deposition (railway::deposition_text), so
// settings of the push, the tamping, the consolidation or the settling share it.
std::string deposition_key(const railway::PushStudyConfig& config, std::uint64_t seed);

// The key of a model's prepared bed on `seed` (shared/KEY/packing.h5), shared likewise.
std::string prepared_bed_key(const railway::PushStudyConfig& config, const Model& model, std::uint64_t seed);

struct RunContext {
  std::string revision;  // of the code
  bool quiet = true;     // the runs' own tables and progress lines
};

// The run of `model` on `seed` (config.seed is replaced): found in the store or computed there.
// A run that fails (unstable, a parameter the bed refuses) is recorded as failed.
runs::RunStore::Outcome ensure_push_run(runs::RunStore& store, const railway::PushStudyConfig& config,
                                        const Model& model, std::uint64_t seed, const RunContext& context);

// What the runs being computed in the store are doing, from the line each writes while it runs
// (scene::ProgressMirror into this file of its work folder): "s1-all-clump settle 34 %, ...";
// empty when none runs. A study's reporting process shows it while its runs compute.
inline constexpr const char* kRunProgressFile = "progress.txt";
std::string running_runs(const runs::RunStore& store);

// Names of the numbers a push run records (run.toml [numbers]), for readers of the store.
namespace number {
inline constexpr const char* kPeakForce = "peak_force";                  // N
inline constexpr const char* kMaxContactForce = "max_contact_force";     // N
inline constexpr const char* kContactForceQ999 = "contact_force_q999";   // N
inline constexpr const char* kMeanForce = "mean_force";                  // N
inline constexpr const char* kClumps = "clumps";
inline constexpr const char* kBalls = "balls";
inline constexpr const char* kElements = "elements";
inline constexpr const char* kContactsAtPeak = "contacts_at_peak";
inline constexpr const char* kPreparationWall = "preparation_wall_seconds";  // the model's stages after the deposition
inline constexpr const char* kPushWall = "push_wall_seconds";
inline constexpr const char* kDepositionWall = "deposition_wall_seconds";    // shared by the seed's runs
inline constexpr const char* kSeed = "seed";
inline constexpr const char* kTimeStep = "time_step";                    // s, of the push
inline constexpr const char* kSteps = "steps";                           // of the push
}  // namespace number

}  // namespace mfdem::campaigns
