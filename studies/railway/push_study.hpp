#pragma once
// The push study: prepare a bed (optionally as a model's own bed, converted at the deposition),
// convert and re-settle a finished one when asked, push its sleeper, check the rate. The one
// orchestration that `mfdem pack`, `push`, `push-test` and every multi-run study (compare,
// statistics, calibration) call; the command line only parses options into these requests.
//
// The model is the config's [fidelity] (policy, rolling_friction, ball_friction): callers that
// take a model from elsewhere (a command line option, a study's list) write it there and name
// where it came from in `model_origin`, which every refusal of the policy quotes.
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <utility>

#include "fidelity/policy.hpp"
#include "studies/railway/bed_preparation.hpp"
#include "studies/railway/push_output.hpp"

namespace mfdem::railway {

// The policy that converts nothing: the reference model.
inline constexpr const char* kReferencePolicy = "all-clump";

struct PackRequest {
  std::filesystem::path out;     // packing.h5 (and checkpoint.h5 while it runs) go here
  bool quiet = false;
  bool keep_stages = false;      // also the stages' states (deposit.h5, settle.h5, ...)
  bool resume = false;           // go on from out/checkpoint.h5
  bool start_over = false;       // remove an earlier pack's checkpoint instead of refusing it
  std::string stop_after;        // a stage (stopping_points); the packing is then not written
  std::filesystem::path deposit_from;   // a deposited bed's checkpoint.h5 (or its directory)
  std::filesystem::path continue_from;  // a finished packing.h5 (or its directory)
  std::string model_origin;      // where config.fidelity.policy came from ("" = the config key)
};

struct PackOutcome {
  std::optional<std::filesystem::path> packing;  // none when stopped by stop_after
  PreparationReport report;
};

// Prepares the bed of `config` (its seed) into request.out. A policy other than all-clump is
// made at the deposition (converted there, unless continuing a finished packing). Throws
// config::ConfigError for a bad policy (before any work), std::runtime_error for a checkpoint or
// packing that would be overwritten, dem::StabilityError when a stage turns unstable (the last
// good stage's bed stays in out/checkpoint.h5).
PackOutcome pack_bed(const PushStudyConfig& config, const PackRequest& request, std::ostream& out);

struct PushRequest {
  std::filesystem::path out;                 // push.h5, push_summary.toml, push_state.h5 go here
  std::optional<double> velocity, distance;  // m/s, m; default: the config's [push]
  bool check_rate = false;                   // again at half the velocity (out/half_velocity)
  bool quiet = false;
  // true: convert the bed by config.fidelity (a finished all-clump packing: grown and re-settled).
  // false: a model's own packing is pushed as it was made.
  bool convert = true;
  std::string revision;                      // of the code, recorded in every output
  std::string model_origin;                  // as PackRequest's
};

struct PushOutcome {
  PushResult result;
  std::optional<PushResult> half_velocity;   // with check_rate, when the first push finished
  std::optional<RateCheck> rate;
  bool finished() const {
    return result.status == "finished" && (!half_velocity || half_velocity->status == "finished");
  }
};

// The packing file a command is given: packing.h5 itself, or the directory `mfdem pack` wrote (its
// checkpoint.h5 when it holds no packing.h5, so that a stopped pack is named as such).
std::filesystem::path packing_file(const std::filesystem::path& given);

// Pushes the sleeper of `packing` (loaded from `packing_path`, whose stage reports a model's
// record reads) with the materials, guards, push settings and model of `config`. Throws
// config::ConfigError for a bad policy or push setting (before any work) and dem::StabilityError
// when the re-settling turns unstable (out/resettle.h5 keeps its last good state); an unstable
// push returns its result up to the last good state, status "unstable".
PushOutcome push_bed(const Packing& packing, const std::filesystem::path& packing_path,
                     const PushStudyConfig& config, const PushRequest& request, std::ostream& out);

// Checks a push's velocity and distance before any work: finite, the velocity positive, the
// distance at least one record interval (run_push checks that the step count they make is one the
// solver can count). Throws config::ConfigError naming `origin` (the option or key that gave them).
void check_push_motion(double velocity, double distance, double record_interval, const std::string& origin);
// The velocity and distance a request pushes with (its own, else the config's [push]), checked as
// above, naming the options or the config that gave them: (m/s, m).
std::pair<double, double> push_motion(const PushStudyConfig& config, const PushRequest& request);

// The preparation's table (stages, time, force ratio, sleeper base).
void print_preparation(std::ostream& out, const Packing& packing, const PreparationReport& report);

}  // namespace mfdem::railway
