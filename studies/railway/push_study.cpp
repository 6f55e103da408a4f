#include "studies/railway/push_study.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <vector>

#include "dem/stability.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/model_bed.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::railway {
namespace {

namespace fs = std::filesystem;
constexpr double kRiseWarning = 2e-3;  // m: a re-settling that lifts the sleeper more is worth a warning
// A quasi-static push runs at mm/s to cm/s; past these the numbers are typos, and the step count
// of a push of 1e4 simulated seconds (about 1e9 steps of a few microseconds) is a year's run.
constexpr double kFastestPush = 10.0;   // m/s
constexpr double kLongestPush = 1e4;    // s

// The policy checked against a bed whose sleeper base lies `scale` above the floor; a bad one is
// a config error naming the option or the config key that gave it.
fidelity::Policy checked_policy(const PushStudyConfig& config, const std::string& origin,
                                const fidelity::BedScale& scale, const std::string& bed) {
  try {
    return fidelity::PolicyRegistry::builtin().make(config.fidelity.policy, scale);
  } catch (const fidelity::PolicyError& e) {
    const std::string given = origin.empty() ? fmt::format("{}: fidelity.policy = \"{}\"", config.source.string(),
                                                           config.fidelity.policy)
                                             : origin;
    throw config::ConfigError(fmt::format("{}: {} ({})", given, e.what(), bed));
  }
}

// What a push leaves in its folder (push_output.hpp): an earlier push's are removed before a new
// one starts, so that no file of it stands beside the new run's as if it were the new run's.
const std::vector<std::string> kPushOutputs = {"push.h5",          "push_summary.toml", "push_state.h5",
                                                "push_state.xdmf",  "rate_check.toml",   "half_velocity",
                                                "model_packing.h5", "model_packing.xdmf", "resettle.h5",
                                                "resettle.xdmf"};

void remove_earlier(const fs::path& directory, const std::vector<std::string>& names, bool quiet, std::ostream& out) {
  int removed = 0;
  for (const auto& name : names) removed += fs::remove_all(directory / name) > 0 ? 1 : 0;
  if (removed > 0 && !quiet)
    fmt::print(out, "Replacing the earlier results in {} ({} files removed first)\n", directory.string(), removed);
}

// Written beside `path` and renamed over it: a reader sees the old file or the whole new one.
template <class Write>
void write_whole(const fs::path& path, Write&& write) {
  fs::path partial = path;
  partial += ".partial";
  write(partial);
  fs::rename(partial, path);
}

void warn_unsettled(const PreparationReport& report) {
  for (const auto& s : report.stages)
    if (!s.settled)
      fmt::print(std::cerr, "mfdem: warning: stage '{}' stopped at its time limit, unbalanced force ratio {:.2e}\n",
                 s.name, s.unbalanced_force_ratio);
}

}  // namespace

fs::path packing_file(const fs::path& given) {
  if (!fs::is_directory(given)) return given;
  // A folder of a pack that stopped holds its checkpoint only: the checkpoint is named, and refused.
  if (!fs::exists(given / "packing.h5") && fs::exists(given / "checkpoint.h5")) return given / "checkpoint.h5";
  return given / "packing.h5";
}

void print_preparation(std::ostream& out, const Packing& p, const PreparationReport& r) {
  const std::string origin = r.continued_from.empty()
                                 ? fmt::format("{} generated, {} trimmed", r.stones_generated, r.stones_removed)
                                 : "continued from " + r.continued_from;
  fmt::print(out, "\nPacked bed: {} (seed {}): {} stones, {} elements ({}), time step {:.3g} s\n", p.config.name,
             p.config.seed, p.stones.size(), p.element_count(), origin, r.time_step);
  // The stage column as wide as its longest name ("consolidate"); wall times up to "59 min 59 s".
  std::size_t name_width = std::string("stage").size();
  for (const auto& s : r.stages) name_width = std::max(name_width, s.name.size());
  fmt::print(out, "  {:<{}} {:>12} {:>10} {:>16} {:>9} {:>12} {:>16}\n", "stage", name_width, "simulated s", "steps",
             "unbalanced ratio", "settled", "wall", "sleeper base (m)");
  for (const auto& s : r.stages)
    fmt::print(out, "  {:<{}} {:>12.4f} {:>10} {:>16.2e} {:>9} {:>12} {:>16}\n", s.name, name_width, s.simulated_time,
               s.steps, s.unbalanced_force_ratio, !s.settled ? "NO" : s.settled_by_creep ? "by creep" : "yes", scene::format_duration(s.wall_seconds),
               s.sleeper_base ? fmt::format("{:.5f}", *s.sleeper_base) : "-");
  fmt::print(out, "  sleeper base at z = {:.4f} m (design {:.4f} m)\n", dem::box_bottom(p.sleeper),
             p.config.geometry.sleeper_base());
}

PackOutcome pack_bed(const PushStudyConfig& config, const PackRequest& request, std::ostream& out) {
  // A model other than all-clump is made at the deposition: converted there, it is prepared as
  // the model's own bed (studies/presets/README.md says why).
  std::optional<fidelity::Policy> model;
  if (config.fidelity.policy != kReferencePolicy)
    model = checked_policy(config, request.model_origin, {config.geometry.sleeper_base()},
                           fmt::format("the design sleeper base lies {:.4f} m above the floor",
                                       config.geometry.sleeper_base()));
  fs::create_directories(request.out);
  PreparationControl control;
  control.quiet = request.quiet;
  control.stage_directory = request.keep_stages ? request.out : fs::path();
  control.checkpoint = request.out / "checkpoint.h5";
  control.resume = request.resume;
  control.stop_after = request.stop_after;
  if (request.continue_from.empty()) control.convert_after_deposit = model;  // a finished bed is not converted again
  if (!request.deposit_from.empty()) {
    const fs::path from = request.deposit_from;
    control.deposit_from = fs::is_directory(from) ? from / "checkpoint.h5" : from;
    if (fs::exists(control.deposit_from) && fs::equivalent(control.deposit_from, control.checkpoint))
      throw std::runtime_error(fmt::format("--deposit-from {} is this run's own checkpoint, which its stages "
                                           "overwrite; give another --out", control.deposit_from.string()));
  }
  if (!request.continue_from.empty()) {
    control.continue_from = packing_file(request.continue_from);
    const fs::path target = request.out / "packing.h5";
    if (fs::exists(control.continue_from) && fs::exists(target) && fs::equivalent(control.continue_from, target))
      throw std::runtime_error(fmt::format("--continue-from {} would be overwritten by the continued packing; "
                                           "give another --out", control.continue_from.string()));
  }
  if (request.start_over) fs::remove(control.checkpoint);
  // A new packing replaces the folder's earlier one and the pushes of it once the inputs are
  // checked, before any work: a push of the folder must never find the old bed while the new one
  // is being made, and a refused command must leave the folder as it was.
  control.before_work = [&] {
    std::vector<std::string> earlier = kPushOutputs;
    earlier.insert(earlier.end(), {"packing.h5", "packing.xdmf"});
    remove_earlier(request.out, earlier, request.quiet, out);
  };
  // A fresh pack would overwrite an earlier one's checkpoint, hours of work at paper size.
  if (!request.resume && fs::exists(control.checkpoint))
    throw std::runtime_error(fmt::format("{} holds the bed of an earlier pack that stopped before its end; go on "
                                         "from it with 'mfdem pack {} --seed {} --out {} --resume', or remove it "
                                         "to start over", control.checkpoint.string(), config.source.string(),
                                         config.seed, request.out.string()));
  PackOutcome outcome;
  const std::optional<Packing> packing = prepare_bed(config, control, outcome.report);
  if (!packing) {
    if (!request.quiet)
      fmt::print(out, "Stopped after stage '{}': the bed is in {}.\nGo on with: mfdem pack {} --seed {} --out {} "
                 "--resume\n", request.stop_after, control.checkpoint.string(), config.source.string(), config.seed,
                 request.out.string());
    return outcome;
  }
  const fs::path file = request.out / "packing.h5";
  save_finished_packing(file, *packing, outcome.report.stages);
  fs::remove(control.checkpoint);  // the packing holds all of it now
  if (!request.quiet) {
    print_preparation(out, *packing, outcome.report);
    fmt::print(out, "  written: {}\n", file.string());
  }
  warn_unsettled(outcome.report);
  outcome.packing = file;
  return outcome;
}

void check_push_motion(double velocity, double distance, double record_interval, const std::string& origin) {
  const auto refuse = [&](const char* what, double value, const std::string& expected) {
    throw config::ConfigError(fmt::format("{}: the push {} is {:.6g} ({})", origin, what, value, expected));
  };
  if (!std::isfinite(velocity) || velocity <= 0.0 || velocity > kFastestPush)
    refuse("velocity", velocity, fmt::format("expected a speed > 0 and at most {} m/s", kFastestPush));
  if (!std::isfinite(distance) || distance < record_interval)
    refuse("distance", distance,
           fmt::format("expected a finite displacement of at least one record interval, {:.3g} m", record_interval));
  if (distance / velocity > kLongestPush)
    refuse("duration distance / velocity", distance / velocity,
           fmt::format("s; expected at most {:.0e} s of simulated time", kLongestPush));
}

std::pair<double, double> push_motion(const PushStudyConfig& config, const PushRequest& request) {
  const double velocity = request.velocity.value_or(config.push.velocity);
  const double distance = request.distance.value_or(config.push.distance);
  const std::string given = request.velocity && request.distance ? "--velocity, --distance"
                            : request.velocity                      ? "--velocity"
                            : request.distance                      ? "--distance"
                                                                    : config.source.string() + ": [push]";
  check_push_motion(velocity, distance, config.push.record_interval, given);
  return {velocity, distance};
}

PushOutcome push_bed(const Packing& packing, const fs::path& packing_path, const PushStudyConfig& given_config,
                     const PushRequest& request, std::ostream& out) {
  PushStudyConfig config = given_config;
  // A model's own bed (made by `mfdem pack` with a policy) is pushed as it is, unless asked.
  if (!packing.model.empty() && !request.convert) config.fidelity.policy = kReferencePolicy;
  const fidelity::BedScale scale = bed_frame(packing).scale();
  const fidelity::Policy policy =
      checked_policy(config, request.model_origin, scale,
                     fmt::format("the bed of {} has its sleeper base {:.4f} m above the floor",
                                 packing_path.string(), scale.sleeper_base));
  PushRun run;
  std::tie(run.velocity, run.distance) = push_motion(config, request);
  run.quiet = request.quiet;
  fs::create_directories(request.out);
  remove_earlier(request.out, kPushOutputs, request.quiet, out);
  // Until the push ends its summary says so: a folder of a killed run is visibly partial.
  write_whole(request.out / "push_summary.toml", [&](const fs::path& p) {
    std::ofstream running(p);
    running << "# mfdem push summary: this push has not finished (running, or stopped before its end)\n"
            << "status = \"running\"\n";
  });
  ModelControl model_control;
  model_control.quiet = request.quiet;
  model_control.stage_directory = request.out;
  const ModelBed model = [&] {
    try {
      return model_bed(packing, config, policy, model_control);
    } catch (const dem::StabilityError&) {
      fmt::print(std::cerr, "mfdem: the converted bed ({}) and its last good state while re-settling are in {}\n",
                 policy.describe(), (request.out / "resettle.h5").string());
      throw;
    }
  }();
  if (model.report.resettling) {
    const double rise = *model.report.resettling->sleeper_base - *model.report.resettling->sleeper_base_start;
    if (rise > kRiseWarning)
      fmt::print(std::cerr,
                 "mfdem: warning: growing the balls in the finished packing lifted the sleeper by {:.1f} mm (the "
                 "bed dilated around them); a model prepared from the deposition ('mfdem pack CONFIG --fidelity "
                 "{}', sharing it with --deposit-from) sits as the reference does (studies/presets/README.md)\n",
                 rise * 1e3, config.fidelity.policy);
    Packing saved = model.packing;
    saved.config = config;
    save_finished_packing(request.out / "model_packing.h5", saved, {*model.report.resettling});
  }
  run.state_file = request.out / "push_state.h5";
  PushOutcome outcome;
  PushResult& result = outcome.result;
  result = run_push(model.packing, config, run);
  result.model = model.report;
  // A model made at the deposition: its preparation from the conversion on stands for the re-settling.
  if (!result.model.resettling && !packing.model.empty())
    result.model.resettling = model_preparation(read_stage_reports(packing_path));
  result.revision = request.revision;
  write_whole(request.out / "push.h5", [&](const fs::path& p) { write_push_file(p, result); });
  write_whole(request.out / "push_summary.toml", [&](const fs::path& p) { write_push_summary(p, result, packing); });
  if (!request.quiet) {
    print_push_summary(out, result, packing);
    fmt::print(out, "  written: {}\n", (request.out / "push.h5").string());
  }
  if (result.status != "finished" || !request.check_rate) return outcome;
  PushRun slow = run;
  slow.velocity = 0.5 * run.velocity;
  const fs::path half_dir = request.out / "half_velocity";
  fs::create_directories(half_dir);
  slow.state_file = half_dir / "push_state.h5";
  PushResult half = run_push(model.packing, config, slow);
  half.model = result.model;
  half.revision = result.revision;
  write_whole(half_dir / "push.h5", [&](const fs::path& p) { write_push_file(p, half); });
  write_whole(half_dir / "push_summary.toml", [&](const fs::path& p) { write_push_summary(p, half, packing); });
  const RateCheck check = compare_rates(result, half);
  write_whole(request.out / "rate_check.toml", [&](const fs::path& p) { write_rate_check(p, check); });
  if (!request.quiet) {
    print_rate_check(out, result, half, check);
    fmt::print(out, "  written: {}\n", (request.out / "rate_check.toml").string());
  }
  outcome.half_velocity = std::move(half);
  outcome.rate = check;
  return outcome;
}

}  // namespace mfdem::railway
