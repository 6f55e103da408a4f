#include <memory>

#include "studies/cli/commands.hpp"
#include "studies/cli/common_options.hpp"
#include "studies/cli/subcommands.hpp"

namespace mfdem::cli {

void add_run_command(CLI::App& app, Action& action) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* run = app.add_subcommand("run", "Simulate a scene file and write its results under --out");
  run->footer(
      "Builds the ballast bed, sleeper and walls the scene describes, runs its stages (packing,\n"
      "settling, push) and writes the results under --out. The whole config is checked before\n"
      "anything runs. A physically unstable setting stops the run with a message saying what and\n"
      "where; everything computed up to the last good state is kept.");
  run->add_option("scene", options->scene, "Scene file (TOML), e.g. studies/scenes/demo.toml")->required();
  run->add_flag("--force-dt", options->force_dt,
                "Keep the scene's time step even when it exceeds the stability estimate "
                "(for studies of where stability ends; results may blow up)");
  add_common_options(*run, options->common);
  run->callback([options, &action] {
    action = [options] {
      apply_thread_count(options->common);
      return run_scene_command(*options);
    };
  });
}

}  // namespace mfdem::cli
