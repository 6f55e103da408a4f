#pragma once
// The bed between two preparation stages, saved so that a long preparation can stop and go on
// later (`mfdem pack --resume`, `--stop-after`): a paper-size pack runs for hours, longer than a
// batch job or a session may last, and a crash must not throw away the stages already done. The
// deposited bed, saved before the trimming, can also start other preparations (`--deposit-from`):
// other tamping, consolidation or settling from the same deposition, which is a quarter to a half
// of a pack's cost.
//
// A checkpoint is a packing file (packing.hpp) of the bed as the next stage receives it: the
// stones (sizes and states exactly as held), their records, the domain, the reports of the
// stages done, the sleeper box the next stage starts with (zero-sized before the trimming), plus
// in /packing the attributes next_stage (the stage to run next), trimmed (0 for the deposited
// bed), mean_size (m), stones_generated, stones_removed and time_step (s). Each stage starts a
// new solver from the stones' states (no contact springs carry over between stages), so a
// resumed preparation is bitwise the uninterrupted one.
#include <filesystem>
#include <string>
#include <vector>

#include "dem/simulation.hpp"
#include "studies/railway/packing.hpp"
#include "studies/railway/section_simulation.hpp"
#include "studies/railway/stage_runner.hpp"

namespace mfdem::railway {

struct PreparationReport {
  std::int64_t stones_generated = 0;
  std::int64_t stones_removed = 0;
  double time_step = 0.0;          // s
  std::vector<StageReport> stages;
  std::string continued_from;      // the finished packing its first stages come from, if any
};

struct BedBetweenStages {
  std::vector<dem::ClumpSpec> stones;
  std::vector<StoneRecord> records;  // one per stone
  dem::Vec3 sleeper_centre;          // m, where the last stage left it (its design place until then)
  dem::Domain domain;
  double mean_size = 0.0;            // m, over every stone drawn: the stages' energy scale
  bool trimmed = false;              // false: as deposited, before the trimming and the sleeper's cut
};

// The config text without what acts after the deposition (name, seed, [push], [fidelity] and the
// [preparation] keys of kDeposit below), serialised: equal for configs that deposit the same bed.
std::string deposition_text(const std::string& config_text);

// Writes the checkpoint to `path` (through a temporary file, so a run stopped while writing
// keeps the previous one). `setup` holds the boundaries of the bed's state: the deposition's
// container, or the sleeper box the next stage starts with.
void save_checkpoint(const std::filesystem::path& path, const PushStudyConfig& config, const BedBetweenStages& bed,
                     const StageSetup& setup, const PreparationReport& report, const std::string& next_stage);

// kResume: a checkpoint of the same preparation (the same config text and seed).
// kDeposit: a deposited bed for this config (trimmed = 0; the same config but for the keys that
//   act after the deposition: name, [push], and in [preparation] those of tamping,
//   consolidation, expansion steps and time, and settling).
enum class CheckpointUse { kResume, kDeposit };

// A finished packing as the bed before this config's traffic (`mfdem pack --continue-from`): the
// packing must be made with this config but for the keys that act in the traffic and settling
// (name, [push], and in [preparation] traffic_*, local_damping, equilibrium_ratio and
// max_settling_time), with the same seed (std::runtime_error naming the file and the first
// difference otherwise). Appends its stage reports to `report`; the stages' energy scale
// (mean_size) is the mean sieve size of the stones kept, which a finished packing holds, not of
// every stone drawn.
BedBetweenStages load_finished_bed(const std::filesystem::path& path, const PushStudyConfig& config,
                                   PreparationReport& report);

// Reads a checkpoint for `config` (std::runtime_error naming the file and the first difference
// when it was made for another); appends its stage reports to `report` and returns the bed,
// `next_stage` set to the stage it was saved before.
BedBetweenStages load_checkpoint(const std::filesystem::path& path, const PushStudyConfig& config, CheckpointUse use,
                                 PreparationReport& report, std::string& next_stage);

}  // namespace mfdem::railway
