#include "studies/railway/preparation_checkpoint.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <sstream>
#include <stdexcept>

#include "dem/hdf5_io.hpp"

namespace mfdem::railway {
namespace {

namespace fs = std::filesystem;

// The first line where two config texts differ, for a message a person can act on.
std::string first_difference(const std::string& saved, const std::string& given) {
  std::istringstream a(saved), b(given);
  std::string line_a, line_b;
  for (int line = 1;; ++line) {
    const bool more_a = static_cast<bool>(std::getline(a, line_a));
    const bool more_b = static_cast<bool>(std::getline(b, line_b));
    if (!more_a && !more_b) return "they differ";
    if (!more_a || !more_b || line_a != line_b)
      return fmt::format("line {}: '{}' in the checkpoint, '{}' now", line, more_a ? line_a : "(end)",
                         more_b ? line_b : "(end)");
  }
}

}  // namespace

void save_checkpoint(const fs::path& path, const PushStudyConfig& config, const BedBetweenStages& bed,
                     const dem::RigidBox& sleeper, const PreparationReport& report, const std::string& next_stage) {
  Packing p;
  p.config = config;
  p.stones = bed.records;
  p.bodies = bed.stones;
  p.sleeper = sleeper;
  p.sleeper.centre = bed.sleeper_centre;
  p.domain = bed.domain;
  for (const auto& s : report.stages) p.preparation_time += s.simulated_time;
  p.unbalanced_force_ratio = report.stages.empty() ? 0.0 : report.stages.back().unbalanced_force_ratio;
  // Written beside and renamed over the last one: a run stopped mid-write keeps a whole file.
  fs::path partial = path;
  partial.replace_extension(".partial.h5");
  save_packing(partial, p);
  append_stage_reports(partial, report.stages);
  const hid_t file = H5Fopen(partial.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot reopen " + partial.string());
  const hid_t g = H5Gopen2(file, "packing", H5P_DEFAULT);
  dem::h5::write_attribute(g, "next_stage", next_stage);
  dem::h5::write_attribute(g, "mean_size", bed.mean_size);
  dem::h5::write_attribute(g, "stones_generated", static_cast<double>(report.stones_generated));
  dem::h5::write_attribute(g, "stones_removed", static_cast<double>(report.stones_removed));
  dem::h5::write_attribute(g, "time_step", report.time_step);
  H5Gclose(g);
  H5Fclose(file);
  fs::rename(partial, path);
  fs::remove(fs::path(partial).replace_extension(".xdmf"));  // a checkpoint is not for viewing
}

BedBetweenStages load_checkpoint(const fs::path& path, const PushStudyConfig& config, PreparationReport& report,
                                 std::string& next_stage) {
  if (!fs::exists(path))
    throw std::runtime_error(fmt::format("{}: no checkpoint to resume from (expected one written by an earlier "
                                         "`mfdem pack` with the same --out)", path.string()));
  const Packing p = load_packing(path);
  if (p.config.seed != config.seed)
    throw std::runtime_error(fmt::format("{}: made with seed {}, this run has seed {}; resume with --seed {}",
                                         path.string(), p.config.seed, config.seed, p.config.seed));
  if (p.config.text != config.text)
    throw std::runtime_error(fmt::format("{}: made from another config ({}); resume with the config it was made "
                                         "from", path.string(), first_difference(p.config.text, config.text)));
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t g = H5Gopen2(file, "packing", H5P_DEFAULT);
  next_stage = dem::h5::read_text_attribute(g, "next_stage");
  BedBetweenStages bed;
  try {
    if (next_stage.empty())
      throw std::runtime_error("no /packing attribute next_stage: a finished packing, not a checkpoint");
    bed.mean_size = dem::h5::read_attribute(g, "mean_size");
    report.stones_generated = static_cast<std::int64_t>(dem::h5::read_attribute(g, "stones_generated"));
    report.stones_removed = static_cast<std::int64_t>(dem::h5::read_attribute(g, "stones_removed"));
    report.time_step = dem::h5::read_attribute(g, "time_step");
  } catch (const std::exception& e) {
    H5Gclose(g);
    H5Fclose(file);
    throw std::runtime_error(fmt::format("{}: {}", path.string(), e.what()));
  }
  H5Gclose(g);
  H5Fclose(file);
  for (auto& s : read_stage_reports(path)) report.stages.push_back(std::move(s));
  bed.stones = p.bodies;
  bed.records = p.stones;
  bed.sleeper_centre = p.sleeper.centre;
  bed.domain = p.domain;
  return bed;
}

}  // namespace mfdem::railway
