#pragma once
// The bed between two preparation stages, saved so that a long preparation can stop and go on
// later (`mfdem pack --resume`, `--stop-after`): a paper-size pack runs for hours, longer than a
// batch job or a session may last, and a crash must not throw away the stages already done.
//
// A checkpoint is a packing file (packing.hpp) of the bed as the next stage receives it: the
// stones (sizes and states exactly as held), their records, the sleeper where the last stage
// left it (its size is the config's), the domain, the reports of the stages done, plus in
// /packing the attributes next_stage (the stage to run next), mean_size (m), stones_generated,
// stones_removed and time_step (s). Each stage starts a new solver from the stones' states
// (no contact springs carry over between stages), so a resumed preparation is bitwise the
// uninterrupted one.
#include <filesystem>
#include <string>
#include <vector>

#include "dem/simulation.hpp"
#include "studies/railway/packing.hpp"
#include "studies/railway/stage_runner.hpp"

namespace mfdem::railway {

struct PreparationReport {
  std::int64_t stones_generated = 0;
  std::int64_t stones_removed = 0;
  double time_step = 0.0;          // s
  std::vector<StageReport> stages;
};

struct BedBetweenStages {
  std::vector<dem::ClumpSpec> stones;
  std::vector<StoneRecord> records;  // one per stone
  dem::Vec3 sleeper_centre;          // m
  dem::Domain domain;
  double mean_size = 0.0;            // m, over every stone drawn: the stages' energy scale
};

// Writes the checkpoint to `path` (through a temporary file, so a run stopped while writing
// keeps the previous one). `sleeper` is the box the next stage starts with.
void save_checkpoint(const std::filesystem::path& path, const PushStudyConfig& config, const BedBetweenStages& bed,
                     const dem::RigidBox& sleeper, const PreparationReport& report, const std::string& next_stage);

// Reads a checkpoint written for `config` (the same text and seed, or std::runtime_error naming
// the file and the difference); appends its stage reports to `report` and returns the bed,
// `next_stage` set to the stage to run.
BedBetweenStages load_checkpoint(const std::filesystem::path& path, const PushStudyConfig& config,
                                 PreparationReport& report, std::string& next_stage);

}  // namespace mfdem::railway
