#pragma once
// The bed a model is pushed on: a prepared packing re-represented by a fidelity policy
// (fidelity/policy.hpp, fidelity/conversion.hpp) and re-settled.
//
// Two conversion points. The default: the finished packing (all clumps, as `mfdem pack` left it) is converted
// and settled again with the design friction, the settling's local damping and the sleeper free
// across the track and vertically. An equal-volume ball is wider than its clump across the
// clump's short axes and overlaps its neighbours where the clump sat, so each ball starts at the
// radius at which it fits (fidelity::fitting_radii) and grows to its own at a steady rate over
// [fidelity] growth_time, with the deposition's lowered friction and no rolling resistance (the
// bed makes room by rearranging, not by lifting); then the bed settles to the preset's equilibrium criterion
// (equilibrium_ratio, within max_settling_time). So one packing per seed serves every model and every calibration candidate,
// and models differ only in fidelity. A policy that converts no stone (all-clump, h at the
// floor) leaves the packing bitwise as it was, and nothing is re-settled. The alternative
// (`mfdem pack --fidelity`, bed_preparation.hpp): the deposited bed is converted and the stages
// after the deposition run per model; the deposition can be shared (--deposit-from).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "fidelity/conversion.hpp"
#include "studies/railway/ball_growth.hpp"
#include "studies/railway/packing.hpp"

namespace mfdem::railway {

// The model's own record: every output file of a push carries it.
struct ModelReport {
  std::string policy = "all-clump";     // the resolved policy (fidelity::Policy::describe)
  double rolling_friction = 0.0;        // mu_r of the balls
  double ball_friction = 0.0;           // mu of the balls
  std::int64_t clumps = 0, balls = 0;   // stones of each kind
  std::int64_t elements = 0;            // spheres of the stones
  std::int64_t elements_before = 0;     // of the packing as prepared (all clumps: the reference)
  std::int64_t converted = 0;           // stones made balls by the policy
  std::int64_t springs_dropped = 0;     // contact springs of converted stones, not carried over
  std::int64_t reshaped = 0;            // converted stones whose shape changed (not one-pebble clumps)
  // The radius the reshaped balls started the re-settling at, as a fraction of their own
  // (fidelity::fitting_radii): the smallest and the mean.
  double smallest_start_fraction = 1.0, mean_start_fraction = 1.0;
  std::string conversion_point = "none";  // "after preparation, re-settled" or "none"
  std::optional<StageReport> resettling;  // when a stone was converted

  double element_ratio() const { return elements_before ? double(elements) / double(elements_before) : 1.0; }
};

// For a model made at the deposition: its conversion and every stage after it summed (time,
// steps, wall time), with the last stage's force ratio and sleeper base: what a re-settling
// reports for the other point. None when the stages hold no "convert".
std::optional<StageReport> model_preparation(const std::vector<StageReport>& stages);

struct ModelBed {
  Packing packing;
  ModelReport report;
};

// Where the policy measures from: floor at z = 0, the packing's settled sleeper and domain.
fidelity::BedFrame bed_frame(const Packing& packing);

// The policy of `spec`, checked against the packing's settled sleeper base. Throws
// fidelity::PolicyError.
fidelity::Policy make_policy(const std::string& spec, const Packing& packing);

struct ModelControl {
  bool quiet = false;
  // false: push the converted bed as it is (for tests that compare two representations of the
  // same bed; a real model is always re-settled).
  bool resettle = true;
  // When given, the re-settling's frames go there (resettle.h5), and an unstable re-settling
  // leaves its last good state in it (besides the StabilityError it throws).
  std::filesystem::path stage_directory;
};

// Elements of the same stones as all clumps (a ball counts its template's pebbles).
std::int64_t all_clump_elements(const PushStudyConfig& config, const std::vector<dem::ClumpSpec>& bodies,
                                const std::vector<StoneRecord>& stones);

// Converts `packing` by `policy` with the ball material of `config` ([fidelity]) and re-settles
// it when a stone was converted. Throws dem::StabilityError when the re-settling turns unstable.
ModelBed model_bed(const Packing& packing, const PushStudyConfig& config, const fidelity::Policy& policy,
                   const ModelControl& control);

}  // namespace mfdem::railway
