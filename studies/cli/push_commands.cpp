// `mfdem pack`, `mfdem push` and `mfdem push-test`: the single-sleeper lateral push test.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "dem/stability.hpp"
#include "studies/cli/common_options.hpp"
#include "studies/cli/subcommands.hpp"
#include "studies/cli/version.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/push_study.hpp"

namespace mfdem::cli {
namespace {

namespace fs = std::filesystem;
constexpr int kUnstable = 3;  // as `mfdem run`

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

// The config's [fidelity] with the command line's choices on top; returns where the policy came
// from, for the messages that refuse it ("" when from the config).
std::string apply_model_options(const ModelOptions& o, railway::PushStudyConfig& config) {
  if (o.fidelity) config.fidelity.policy = *o.fidelity;
  if (o.rolling_friction) config.fidelity.rolling_friction = *o.rolling_friction;
  if (o.ball_friction) config.fidelity.ball_friction = *o.ball_friction;
  return o.fidelity ? fmt::format("--fidelity {}", *o.fidelity) : std::string();
}

// Packs into options.out; returns the packing file, or none when stopped by --stop-after.
std::optional<fs::path> pack(const PackOptions& o, bool start_over = false) {
  railway::PushStudyConfig config = railway::load_push_config(o.config);
  if (o.common.seed_given) config.seed = o.common.seed;
  railway::PackRequest request;
  request.model_origin = apply_model_options(o.model, config);
  request.out = o.common.out;
  request.quiet = o.common.quiet;
  request.keep_stages = o.keep_stages;
  request.resume = o.resume;
  request.start_over = start_over;
  request.stop_after = o.stop_after;
  request.deposit_from = o.deposit_from;
  request.continue_from = o.continue_from;
  return railway::pack_bed(config, request, std::cout).packing;
}

// The push's velocity and distance as options give them (mm to m).
railway::PushRequest motion_of(const PushOptions& o) {
  railway::PushRequest request;
  if (o.velocity_mm_s) request.velocity = *o.velocity_mm_s * 1e-3;
  if (o.distance_mm) request.distance = *o.distance_mm * 1e-3;
  return request;
}

int push(const PushOptions& o, const fs::path& packing_path) {
  // The packing's own config unless --config; read before any work so that a bad one stops here.
  if (const auto stage = railway::checkpoint_stage(packing_path))
    throw config::ConfigError(fmt::format(
        "{} is a checkpoint of a preparation saved before its stage '{}', not a finished packing: finish it with "
        "`mfdem pack CONFIG --resume --out FOLDER`, or prepare a bed from a deposition with `mfdem pack CONFIG "
        "--deposit-from FOLDER`", packing_path.string(), *stage));
  const railway::Packing packing = railway::load_packing(packing_path);
  railway::PushStudyConfig config = o.config ? railway::load_push_config(o.config->string()) : packing.config;
  railway::PushRequest request = motion_of(o);
  request.model_origin = apply_model_options(o.model, config);
  request.convert = o.model.fidelity.has_value();
  request.out = o.common.out;
  request.quiet = o.common.quiet;
  request.check_rate = o.check_rate;
  request.revision = git_revision();
  const railway::PushOutcome outcome = railway::push_bed(packing, packing_path, config, request, std::cout);
  return outcome.finished() ? 0 : kUnstable;
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
      ->check(finite_positive("mm/s"));
  command.add_option_function<double>("--distance", [&o](const double& d) { o.distance_mm = d; },
                                      "Push distance u_end in mm (default: the config's, 5 mm)")
      ->check(finite_positive("mm"));
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
                           "A preset (mini, study, standard, paper) or a study config file (TOML)")->required();
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
      if (push_options->common.seed_given)
        throw config::ConfigError(fmt::format("--seed {}: a push has no seed of its own; the bed, and its seed, are "
                                              "the packing's (pack another seed with 'mfdem pack --seed')",
                                              push_options->common.seed));
      apply_thread_count(push_options->common);
      return guarded([&] { return push(*push_options, railway::packing_file(push_options->packing)); });
    };
  });

  auto one_shot = std::make_shared<PushOptions>();
  CLI::App* test_command =
      app.add_subcommand("push-test", "Prepare a bed and push its sleeper in one go (pack, then push)");
  test_command->add_option("config", one_shot->packing, "A preset (mini, study, standard, paper) or a study config file")
      ->required();
  add_push_options(*test_command, *one_shot);
  add_common_options(*test_command, one_shot->common);
  test_command->callback([one_shot, &action] {
    action = [one_shot] {
      apply_thread_count(one_shot->common);
      return guarded([&] {
        // The push's settings checked before the pack's hours of work.
        railway::push_motion(railway::load_push_config(one_shot->packing), motion_of(*one_shot));
        PackOptions p;
        p.common = one_shot->common;
        p.config = one_shot->packing;
        p.model = one_shot->model;  // a model is made at the deposition (pack checks it before any work)
        PushOptions as_packed = *one_shot;
        as_packed.model.fidelity.reset();
        // The one-shot form always starts over (an interrupted demo reruns as typed); `mfdem
        // pack` refuses to overwrite a checkpoint instead. Pushed from the file just written, so
        // the push is bitwise the one `mfdem push` makes.
        return push(as_packed, *pack(p, true));
      });
    };
  });
}

}  // namespace mfdem::cli
