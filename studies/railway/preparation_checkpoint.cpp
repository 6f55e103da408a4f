#include "studies/railway/preparation_checkpoint.hpp"

#include <fmt/format.h>
#include <hdf5.h>
#include <toml++/toml.h>

#include <array>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "dem/hdf5_io.hpp"

namespace mfdem::railway {
namespace {

namespace fs = std::filesystem;

// The [preparation] keys that act only after the deposition (and the trimming, which is redone).
constexpr std::array<std::string_view, 15> kAfterDeposition = {
    "tamping_depth", "tamping_time", "tamping_sleeper_vertical", "consolidation_gravity", "consolidation_time",
    "expansion_steps", "expansion_time", "traffic_cycles", "traffic_load", "traffic_period", "local_damping",
    "equilibrium_ratio", "max_settling_time", "creep_ratio", "creep_window"};

// The [preparation] keys that act in the traffic and the settling after it.
constexpr std::array<std::string_view, 8> kTrafficAndSettling = {
    "traffic_cycles", "traffic_load", "traffic_period", "local_damping", "equilibrium_ratio", "max_settling_time",
    "creep_ratio", "creep_window"};

// The first line where two config texts differ, for a message a person can act on.
std::string first_different_line(const std::string& saved, const std::string& given) {
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

std::string shown(const toml::node* n) {
  if (!n) return "absent";
  if (const auto* x = n->as_floating_point()) return fmt::format("{}", x->get());  // shortest, as typed
  std::ostringstream out;
  out << toml::node_view<const toml::node>(n);
  return out.str();
}

// The first key (dotted) whose value differs between two tables, with both values; "" if none.
// `saved` names the file `a` was read from ("checkpoint", "packing").
std::string first_different_key(const toml::table& a, const toml::table& b, const std::string& prefix,
                                std::string_view saved = "checkpoint") {
  for (auto&& [k, v] : a) {
    const std::string key = prefix + std::string(k.str());
    const toml::node* w = b.get(k.str());
    if (w && v.is_table() && w->is_table()) {
      const std::string inner = first_different_key(*v.as_table(), *w->as_table(), key + ".", saved);
      if (!inner.empty()) return inner;
    } else if (!w || toml::node_view<const toml::node>(&v) != toml::node_view<const toml::node>(w)) {
      return fmt::format("{} = {} in the {}, {} now", key, shown(&v), saved, shown(w));
    }
  }
  for (auto&& [k, v] : b)
    if (!a.contains(k.str()))
      return fmt::format("{} = absent in the {}, {} now", prefix + std::string(k.str()), saved, shown(&v));
  return "";
}

// The config without `later` of [preparation] (and name, seed, [push], [fidelity]): what made
// the bed before.
template <std::size_t N>
toml::table part_before(const std::string& text, const std::array<std::string_view, N>& later) {
  toml::table t = toml::parse(text);
  for (const char* key : {"name", "seed", "push", "fidelity"}) t.erase(key);
  if (toml::table* preparation = t["preparation"].as_table())
    for (const auto key : later) preparation->erase(key);
  return t;
}

// The same stones: the seed draws them, the library shapes them.
void check_same_stones(const fs::path& path, const PushStudyConfig& saved, const PushStudyConfig& config) {
  if (saved.seed != config.seed)
    throw std::runtime_error(fmt::format("{}: made with seed {}, this run has seed {}; use --seed {}", path.string(),
                                         saved.seed, config.seed, saved.seed));
  if (saved.stones.library != config.stones.library)
    throw std::runtime_error(fmt::format("{}: made with the shape library {}, this config's is {}", path.string(),
                                         saved.stones.library.string(), config.stones.library.string()));
}

// Refuses `config` when it differs from `saved` (read from `path`, a `kind` file) in a key other
// than name, seed, [push] and `later` of [preparation]; `what` ({}: the first difference) says why.
template <std::size_t N>
void require_same_before(const fs::path& path, const PushStudyConfig& saved, const PushStudyConfig& config,
                         const std::array<std::string_view, N>& later, std::string_view kind, std::string_view what) {
  const std::string difference =
      first_different_key(part_before(saved.text, later), part_before(config.text, later), "", kind);
  if (!difference.empty())
    throw std::runtime_error(path.string() + ": " + fmt::format(fmt::runtime(what), difference));
}

void check_made_for(const fs::path& path, const PushStudyConfig& saved, const PushStudyConfig& config,
                    CheckpointUse use) {
  check_same_stones(path, saved, config);
  if (use == CheckpointUse::kResume && saved.text != config.text)
    throw std::runtime_error(fmt::format("{}: made from another config ({}); resume with the config it was made "
                                         "from", path.string(), first_different_line(saved.text, config.text)));
  if (use == CheckpointUse::kDeposit)
    require_same_before(path, saved, config, kAfterDeposition, "checkpoint",
                        "deposited with another config ({}); only what acts after the deposition may differ");
}

void check_continued_with(const fs::path& path, const PushStudyConfig& saved, const PushStudyConfig& config) {
  check_same_stones(path, saved, config);
  require_same_before(path, saved, config, kTrafficAndSettling, "packing",
                      "prepared with another config ({}); only the traffic and settling keys may differ");
}

}  // namespace

std::string deposition_text(const std::string& config_text) {
  std::ostringstream text;
  text << part_before(config_text, kAfterDeposition);
  return text.str();
}

void save_checkpoint(const fs::path& path, const PushStudyConfig& config, const BedBetweenStages& bed,
                     const StageSetup& setup, const PreparationReport& report, const std::string& next_stage) {
  Packing p;
  p.config = config;
  p.stones = bed.records;
  p.bodies = bed.stones;
  p.sleeper = setup.sleeper.value_or(dem::RigidBox{});
  if (!setup.sleeper) p.sleeper.half_extent = dem::Vec3::Zero();  // not in the bed yet
  p.sleeper.centre = bed.sleeper_centre;
  p.domain = bed.domain;
  for (const auto& s : report.stages) p.preparation_time += s.simulated_time;
  p.unbalanced_force_ratio = report.stages.empty() ? 0.0 : report.stages.back().unbalanced_force_ratio;
  p.continued_from = report.continued_from;  // a continued pack resumed keeps where it came from
  // Written beside and renamed over the last one: a run stopped mid-write keeps a whole file.
  const fs::path partial = partial_path(path);
  save_packing(partial, p, setup, "preparation checkpoint before stage " + next_stage);
  append_stage_reports(partial, report.stages);
  const hid_t file = H5Fopen(partial.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot reopen " + partial.string());
  const hid_t g = H5Gopen2(file, "packing", H5P_DEFAULT);
  dem::h5::write_attribute(g, "next_stage", next_stage);
  dem::h5::write_attribute(g, "trimmed", bed.trimmed ? 1.0 : 0.0);
  dem::h5::write_attribute(g, "mean_size", bed.mean_size);
  dem::h5::write_attribute(g, "stones_generated", static_cast<double>(report.stones_generated));
  dem::h5::write_attribute(g, "stones_removed", static_cast<double>(report.stones_removed));
  dem::h5::write_attribute(g, "time_step", report.time_step);
  H5Gclose(g);
  H5Fclose(file);
  fs::rename(partial, path);
  fs::remove(fs::path(partial).replace_extension(".xdmf"));  // a checkpoint is not for viewing
}

BedBetweenStages load_checkpoint(const fs::path& path, const PushStudyConfig& config, CheckpointUse use,
                                 PreparationReport& report, std::string& next_stage) {
  if (!fs::exists(path))
    throw std::runtime_error(fmt::format("{}: no such checkpoint (expected the checkpoint.h5 that `mfdem pack` "
                                         "writes into its --out directory)", path.string()));
  const Packing p = load_packing(path);
  check_made_for(path, p.config, config, use);
  BedBetweenStages bed;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t g = H5Gopen2(file, "packing", H5P_DEFAULT);
  next_stage = dem::h5::read_text_attribute(g, "next_stage");
  try {
    if (next_stage.empty())
      throw std::runtime_error("no /packing attribute next_stage: a finished packing, not a checkpoint");
    // Checkpoints from before the attribute (595a42c) were all saved after the trimming.
    bed.trimmed = H5Aexists(g, "trimmed") <= 0 || dem::h5::read_attribute(g, "trimmed") != 0.0;
    if (use == CheckpointUse::kDeposit && bed.trimmed)
      throw std::runtime_error(fmt::format("saved before stage '{}', not after the deposition (make one with "
                                           "`mfdem pack CONFIG --stop-after deposit`)", next_stage));
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
  report.continued_from = p.continued_from;
  bed.stones = p.bodies;
  bed.records = p.stones;
  bed.sleeper_centre = p.sleeper.centre;
  bed.domain = p.domain;
  return bed;
}

BedBetweenStages load_finished_bed(const fs::path& path, const PushStudyConfig& config, PreparationReport& report) {
  const Packing p = load_packing(path);  // names the file when it is missing or not a packing
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t g = H5Gopen2(file, "packing", H5P_DEFAULT);
  const bool checkpoint = !dem::h5::read_text_attribute(g, "next_stage").empty();
  H5Gclose(g);
  report.time_step = dem::h5::read_attribute(file, "time_step");
  H5Fclose(file);
  if (checkpoint)
    throw std::runtime_error(fmt::format("{}: a checkpoint, not a finished packing (go on with it by --resume)",
                                         path.string()));
  check_continued_with(path, p.config, config);
  for (auto& s : read_stage_reports(path)) report.stages.push_back(std::move(s));
  report.stones_generated = static_cast<std::int64_t>(p.stones.size());
  BedBetweenStages bed;
  bed.stones = p.bodies;
  bed.records = p.stones;
  bed.sleeper_centre = p.sleeper.centre;
  bed.domain = p.domain;
  bed.trimmed = true;
  for (const auto& s : p.stones) bed.mean_size += s.size / static_cast<double>(p.stones.size());
  return bed;
}

}  // namespace mfdem::railway
