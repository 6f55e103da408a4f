// `mfdem pack`, `mfdem push` and `mfdem push-test`: the single-sleeper lateral push test.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "dem/stability.hpp"
#include "fidelity/policy.hpp"
#include "studies/cli/common_options.hpp"
#include "studies/cli/version.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/model_bed.hpp"
#include "studies/cli/subcommands.hpp"
#include "studies/railway/bed_preparation.hpp"
#include "studies/railway/push_output.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::cli {
namespace {

namespace fs = std::filesystem;
constexpr int kUnstable = 3;  // as `mfdem run`
constexpr const char* kReference = "all-clump";  // the policy that converts nothing
constexpr double kRiseWarning = 2e-3;  // m: a re-settling that lifts the sleeper more is worth a warning

// The model a command runs: replaces the config's [fidelity] policy, rolling_friction, ball_friction.
struct ModelOptions {
  std::optional<std::string> fidelity;
  std::optional<double> rolling_friction, ball_friction;
};

struct PackOptions {
  CommonOptions common;
  ModelOptions model;  // --fidelity: converted after the deposition
  std::string config;
  bool keep_stages = false;
  bool resume = false;
  std::string stop_after;
  std::string deposit_from;
  std::string continue_from;
};

struct PushOptions {
  CommonOptions common;
  std::string packing;          // packing.h5 or a directory holding it (push), config (push-test)
  std::optional<fs::path> config;
  std::optional<double> velocity_mm_s, distance_mm;
  bool check_rate = false;
  ModelOptions model;
};

fs::path packing_file(const fs::path& given) {
  return fs::is_directory(given) ? given / "packing.h5" : given;
}

// The config's [fidelity] with the command line's choices on top.
void apply_model_options(const ModelOptions& o, railway::PushStudyConfig& config) {
  if (o.fidelity) config.fidelity.policy = *o.fidelity;
  if (o.rolling_friction) config.fidelity.rolling_friction = *o.rolling_friction;
  if (o.ball_friction) config.fidelity.ball_friction = *o.ball_friction;
}

// The policy checked against a bed whose sleeper base lies `scale` above the floor; a bad one is
// a config error (exit 2) naming the option or the config key that gave it.
fidelity::Policy checked_policy(const ModelOptions& o, const railway::PushStudyConfig& config,
                                const fidelity::BedScale& scale, const std::string& bed) {
  try {
    return fidelity::PolicyRegistry::builtin().make(config.fidelity.policy, scale);
  } catch (const fidelity::PolicyError& e) {
    const std::string given = o.fidelity ? fmt::format("--fidelity {}", *o.fidelity)
                                         : fmt::format("{}: fidelity.policy = \"{}\"", config.source.string(),
                                                       config.fidelity.policy);
    throw config::ConfigError(fmt::format("{}: {} ({})", given, e.what(), bed));
  }
}

void print_preparation(std::ostream& out, const railway::Packing& p, const railway::PreparationReport& r) {
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
               s.steps, s.unbalanced_force_ratio, s.settled ? "yes" : "NO", scene::format_duration(s.wall_seconds),
               s.sleeper_base ? fmt::format("{:.5f}", *s.sleeper_base) : "-");
  fmt::print(out, "  sleeper base at z = {:.4f} m (design {:.4f} m)\n", dem::box_bottom(p.sleeper),
             p.config.geometry.sleeper_base());
}

// Packs into options.out; returns the packing file, or none when stopped by --stop-after.
std::optional<fs::path> pack(const PackOptions& o) {
  railway::PushStudyConfig config = railway::load_push_config(o.config);
  if (o.common.seed_given) config.seed = o.common.seed;
  // A model other than all-clump (--fidelity or the config's [fidelity]) is made at the deposition:
  // converted there, it is prepared as the model's own bed (studies/presets/README.md says why).
  apply_model_options(o.model, config);
  std::optional<fidelity::Policy> model;
  if (config.fidelity.policy != kReference)
    model = checked_policy(o.model, config, {config.geometry.sleeper_base()},
                           fmt::format("the design sleeper base lies {:.4f} m above the floor",
                                       config.geometry.sleeper_base()));
  fs::create_directories(o.common.out);
  railway::PreparationControl control;
  control.quiet = o.common.quiet;
  control.stage_directory = o.keep_stages ? o.common.out : fs::path();
  control.checkpoint = o.common.out / "checkpoint.h5";
  control.resume = o.resume;
  control.stop_after = o.stop_after;
  if (o.continue_from.empty()) control.convert_after_deposit = model;  // a finished bed is not converted again
  if (!o.deposit_from.empty()) {
    const fs::path from = o.deposit_from;
    control.deposit_from = fs::is_directory(from) ? from / "checkpoint.h5" : from;
    if (fs::exists(control.deposit_from) && fs::equivalent(control.deposit_from, control.checkpoint))
      throw std::runtime_error(fmt::format("--deposit-from {} is this run's own checkpoint, which its stages "
                                           "overwrite; give another --out", control.deposit_from.string()));
  }
  if (!o.continue_from.empty()) {
    control.continue_from = packing_file(o.continue_from);
    const fs::path target = o.common.out / "packing.h5";
    if (fs::exists(control.continue_from) && fs::exists(target) && fs::equivalent(control.continue_from, target))
      throw std::runtime_error(fmt::format("--continue-from {} would be overwritten by the continued packing; "
                                           "give another --out", control.continue_from.string()));
  }
  // A fresh pack would overwrite an earlier one's checkpoint, hours of work at paper size.
  if (!o.resume && fs::exists(control.checkpoint))
    throw std::runtime_error(fmt::format("{} holds the bed of an earlier pack that stopped before its end; go on "
                                         "from it with 'mfdem pack {} --seed {} --out {} --resume', or remove it "
                                         "to start over", control.checkpoint.string(), o.config, config.seed,
                                         o.common.out.string()));
  railway::PreparationReport report;
  const std::optional<railway::Packing> packing = railway::prepare_bed(config, control, report);
  if (!packing) {
    fmt::print("Stopped after stage '{}': the bed is in {}.\nGo on with: mfdem pack {} --seed {} --out {} --resume\n",
               o.stop_after, control.checkpoint.string(), o.config, config.seed, o.common.out.string());
    return std::nullopt;
  }
  const fs::path file = o.common.out / "packing.h5";
  railway::save_finished_packing(file, *packing, report.stages);
  fs::remove(control.checkpoint);  // the packing holds all of it now
  print_preparation(std::cout, *packing, report);
  fmt::print("  written: {}\n", file.string());
  for (const auto& s : report.stages)
    if (!s.settled)
      fmt::print(std::cerr, "mfdem: warning: stage '{}' stopped at its time limit, unbalanced force ratio {:.2e}\n",
                 s.name, s.unbalanced_force_ratio);
  return file;
}

int push(const PushOptions& o, const fs::path& packing_path) {
  const railway::Packing packing = railway::load_packing(packing_path);
  railway::PushStudyConfig config = o.config ? railway::load_push_config(o.config->string()) : packing.config;
  apply_model_options(o.model, config);
  // A model's own bed (made by `mfdem pack` with a policy) is pushed as it is, unless asked.
  if (!packing.model.empty() && !o.model.fidelity) config.fidelity.policy = kReference;
  const fidelity::BedScale scale = railway::bed_frame(packing).scale();
  const fidelity::Policy policy = checked_policy(
      o.model, config, scale,
      fmt::format("the bed of {} has its sleeper base {:.4f} m above the floor", packing_path.string(),
                  scale.sleeper_base));
  railway::PushRun run;
  run.velocity = o.velocity_mm_s ? *o.velocity_mm_s * 1e-3 : config.push.velocity;
  run.distance = o.distance_mm ? *o.distance_mm * 1e-3 : config.push.distance;
  run.quiet = o.common.quiet;
  fs::create_directories(o.common.out);
  railway::ModelControl model_control;
  model_control.quiet = o.common.quiet;
  model_control.stage_directory = o.common.out;
  const railway::ModelBed model = [&] {
    try {
      return railway::model_bed(packing, config, policy, model_control);
    } catch (const dem::StabilityError&) {
      fmt::print(std::cerr, "mfdem: the converted bed ({}) and its last good state while re-settling are in {}\n",
                 policy.describe(), (o.common.out / "resettle.h5").string());
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
    railway::Packing saved = model.packing;
    saved.config = config;
    railway::save_finished_packing(o.common.out / "model_packing.h5", saved, {*model.report.resettling});
  }
  run.state_file = o.common.out / "push_state.h5";
  railway::PushResult result = railway::run_push(model.packing, config, run);
  result.model = model.report;
  // A model made at the deposition: its preparation from the conversion on stands for the re-settling.
  if (!result.model.resettling && !packing.model.empty())
    result.model.resettling = railway::model_preparation(railway::read_stage_reports(packing_path));
  result.revision = git_revision();
  railway::write_push_file(o.common.out / "push.h5", result);
  railway::write_push_summary(o.common.out / "push_summary.toml", result, packing);
  railway::print_push_summary(std::cout, result, packing);
  fmt::print("  written: {}\n", (o.common.out / "push.h5").string());
  if (result.status != "finished") return kUnstable;
  if (!o.check_rate) return 0;
  railway::PushRun slow = run;
  slow.velocity = 0.5 * run.velocity;
  const fs::path half_dir = o.common.out / "half_velocity";
  fs::create_directories(half_dir);
  slow.state_file = half_dir / "push_state.h5";
  railway::PushResult half = railway::run_push(model.packing, config, slow);
  half.model = result.model;
  half.revision = result.revision;
  railway::write_push_file(half_dir / "push.h5", half);
  railway::write_push_summary(half_dir / "push_summary.toml", half, packing);
  const railway::RateCheck check = railway::compare_rates(result, half);
  railway::print_rate_check(std::cout, result, half, check);
  railway::write_rate_check(o.common.out / "rate_check.toml", check);
  fmt::print("  written: {}\n", (o.common.out / "rate_check.toml").string());
  return half.status == "finished" ? 0 : kUnstable;
}

int guarded(const std::function<int()>& work) {
  try {
    return work();
  } catch (const dem::StabilityError& e) {
    fmt::print(std::cerr, "mfdem: unstable: {}\n", e.what());
    return kUnstable;
  }
}

void add_model_options(CLI::App& command, ModelOptions& o, const std::string& when) {
  command.add_option_function<std::string>("--fidelity", [&o](const std::string& p) { o.fidelity = p; },
                                           "The model: a fidelity policy that converts clumps to balls " + when +
                                               ": all-clump, all-ball, layer-by-height:h=M (or h_fraction=F), "
                                               "zone-by-distance:d=M (docs/model.md)");
  command.add_option_function<double>("--rolling-friction", [&o](const double& m) { o.rolling_friction = m; },
                                      "Rolling friction mu_r of the balls (default: the config's [fidelity], 0.3)")
      ->check(CLI::NonNegativeNumber);
  command.add_option_function<double>("--ball-friction", [&o](const double& m) { o.ball_friction = m; },
                                      "Friction mu of the balls (default: the ballast's)")
      ->check(CLI::NonNegativeNumber);
}

void add_push_options(CLI::App& command, PushOptions& o) {
  command.add_option_function<double>("--velocity", [&o](const double& v) { o.velocity_mm_s = v; },
                                      "Sleeper velocity in mm/s (default: the config's [push] velocity)")
      ->check(CLI::PositiveNumber);
  command.add_option_function<double>("--distance", [&o](const double& d) { o.distance_mm = d; },
                                      "Push distance u_end in mm (default: the config's, 5 mm)")
      ->check(CLI::PositiveNumber);
  add_model_options(command, o.model,
                    "before the push (the prepared bed converted and re-settled; default: the config's [fidelity] "
                    "policy, all-clump)");
  command.add_flag("--check-rate", o.check_rate,
                   "Repeat the push at half the velocity (OUT/half_velocity) and report the change of the peak "
                   "force, the mean force and the mean F over each mm (OUT/rate_check.toml)");
}

}  // namespace

void add_push_commands(CLI::App& app, Action& action) {
  auto pack_options = std::make_shared<PackOptions>();
  CLI::App* pack_command = app.add_subcommand("pack", "Prepare a seeded ballast bed under a sleeper (packing.h5)");
  pack_command->add_option("config", pack_options->config,
                           "A preset (mini, standard, paper) or a study config file (TOML)")->required();
  pack_command->add_flag("--keep-stages", pack_options->keep_stages,
                         "Also write the deposition and settling stages (OUT/deposit.h5, settle.h5, + .xdmf)");
  CLI::Option* resume_flag = pack_command->add_flag("--resume", pack_options->resume,
                         "Go on from OUT/checkpoint.h5, left by a stopped or interrupted pack with the same "
                         "config and seed");
  pack_command->add_option("--deposit-from", pack_options->deposit_from,
                           "Start from this deposited bed (the checkpoint.h5, or its directory, of a pack stopped "
                           "with --stop-after deposit), made with this config but for tamping, consolidation, "
                           "traffic and settling keys")
      ->excludes(resume_flag);
  CLI::Option* deposit_option = pack_command->get_option("--deposit-from");
  pack_command->add_option("--continue-from", pack_options->continue_from,
                           "Start from this finished packing (packing.h5 or its directory), made with this config "
                           "but for its traffic and settling keys, and add this config's traffic pulses and settling")
      ->excludes(resume_flag)
      ->excludes(deposit_option);
  pack_command->add_option("--stop-after", pack_options->stop_after,
                           "Stop after this stage (deposit, expand, tamp, consolidate, traffic: those the config runs), "
                           "its checkpoint written; go on later with --resume");
  add_model_options(*pack_command, pack_options->model,
                    "after the deposition (the later stages run on the model's bed; share the deposition with "
                    "--deposit-from)");
  pack_command->get_option("--fidelity")->excludes(resume_flag)->excludes("--continue-from");
  add_common_options(*pack_command, pack_options->common);
  pack_command->footer("Writes OUT/packing.h5 (+ .xdmf for ParaView); push it with 'mfdem push OUT'.\n"
                       "After every stage the bed is saved to OUT/checkpoint.h5 (removed once the packing is\n"
                       "written): a pack stopped by --stop-after or killed goes on with --resume; an\n"
                       "unstable stage leaves the last good stage's bed there. A finished bed takes more\n"
                       "traffic with --continue-from (studies/presets/README.md).\n"
                       "The procedure is described in studies/presets/README.md.");
  pack_command->callback([pack_options, &action] {
    action = [pack_options] {
      apply_thread_count(pack_options->common);
      const int status = guarded([&] {
        pack(*pack_options);
        return 0;
      });
      const fs::path checkpoint = pack_options->common.out / "checkpoint.h5";
      if (status == kUnstable && fs::exists(checkpoint))
        fmt::print(std::cerr, "mfdem: the bed after the last finished stage is in {}\n", checkpoint.string());
      return status;
    };
  });

  auto push_options = std::make_shared<PushOptions>();
  CLI::App* push_command = app.add_subcommand("push", "Push the sleeper of a prepared bed laterally");
  push_command->add_option("packing", push_options->packing, "packing.h5, or the directory 'mfdem pack' wrote")
      ->required();
  push_command->add_option_function<std::string>(
      "--config", [o = push_options.get()](const std::string& c) { o->config = c; },
      "Take materials, guards and [push] settings from this config instead of the packing's own");
  add_push_options(*push_command, *push_options);
  add_common_options(*push_command, push_options->common);
  push_command->callback([push_options, &action] {
    action = [push_options] {
      apply_thread_count(push_options->common);
      return guarded([&] { return push(*push_options, packing_file(push_options->packing)); });
    };
  });

  auto one_shot = std::make_shared<PushOptions>();
  CLI::App* test_command =
      app.add_subcommand("push-test", "Prepare a bed and push its sleeper in one go (pack, then push)");
  test_command->add_option("config", one_shot->packing, "A preset (mini, standard, paper) or a study config file")
      ->required();
  add_push_options(*test_command, *one_shot);
  add_common_options(*test_command, one_shot->common);
  test_command->callback([one_shot, &action] {
    action = [one_shot] {
      apply_thread_count(one_shot->common);
      return guarded([&] {
        PackOptions p;
        p.common = one_shot->common;
        p.config = one_shot->packing;
        // The one-shot form always starts over (an interrupted demo reruns as typed); `mfdem
        // pack` refuses to overwrite a checkpoint instead.
        fs::remove(p.common.out / "checkpoint.h5");
        p.model = one_shot->model;  // a model is made at the deposition (pack checks it before any work)
        PushOptions as_packed = *one_shot;
        as_packed.model.fidelity.reset();
        // Pushed from the file just written, so the push is bitwise the one `mfdem push` makes.
        return push(as_packed, *pack(p));
      });
    };
  });
}

}  // namespace mfdem::cli
