// `mfdem plot`: the figures of one or more push folders (F(u), heave, where the resistance comes
// from, and the displacement and force-chain sections through the sleeper), their numbers
// computed here (studies/campaigns/compare_figures.hpp) and drawn by studies/python/mfdem.
#include <hdf5.h>

#include <fmt/format.h>

#include <filesystem>
#include <memory>

#include "dem/hdf5_io.hpp"
#include "studies/campaigns/compare_figures.hpp"
#include "studies/cli/common_options.hpp"
#include "studies/cli/python_figures.hpp"
#include "studies/cli/subcommands.hpp"
#include "studies/config/config_error.hpp"

namespace mfdem::cli {
namespace {

namespace fs = std::filesystem;

struct PlotOptions {
  CommonOptions common;
  std::vector<std::string> runs, labels;
  std::string title;
};

// A push folder's files: its push.h5, and the packing it pushed (in the folder, as in a run
// store, or in its parent, as `mfdem push-test` writes them).
campaigns::RunFiles run_files(const std::string& folder, const std::string& label) {
  const fs::path push = fs::path(folder) / "push.h5";
  if (!fs::exists(push))
    throw config::ConfigError(fmt::format("{}: no push.h5 in it (expected the folder of an `mfdem push` run)", folder));
  for (const fs::path& packing : {fs::path(folder) / "packing.h5", fs::path(folder).parent_path() / "packing.h5"})
    if (fs::exists(packing)) return {label, push, packing};
  throw config::ConfigError(fmt::format("{}: no packing.h5 in it or its parent (the bed it pushed)", folder));
}

double seed_of(const fs::path& push) {
  const hid_t file = H5Fopen(push.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error(fmt::format("{}: cannot open it as an HDF5 file", push.string()));
  double seed = 0.0;
  try {
    seed = dem::h5::read_attribute(file, "seed");
  } catch (...) {
  }
  H5Fclose(file);
  return seed;
}

int plot(const PlotOptions& o) {
  if (!o.labels.empty() && o.labels.size() != o.runs.size())
    throw config::ConfigError(fmt::format("--labels: {} labels for {} push folders (give one per folder)",
                                          o.labels.size(), o.runs.size()));
  std::vector<campaigns::RunFiles> runs;
  for (std::size_t k = 0; k < o.runs.size(); ++k)
    runs.push_back(run_files(o.runs[k], o.labels.empty() ? o.runs[k] : o.labels[k]));
  fs::create_directories(o.common.out);
  const std::string title = o.title.empty() ? fs::path(o.runs.front()).filename().string() : o.title;
  campaigns::write_push_figure_data(o.common.out / "figures.h5", title,
                                    static_cast<std::uint64_t>(seed_of(runs.front().push)), runs);
  std::vector<std::string> args = {o.common.out.string()};
  for (const auto& r : runs) args.push_back(r.push.parent_path().string());
  if (o.common.quiet) args.push_back("--quiet");
  return draw_figures("push_figures", args) ? 0 : 1;
}

}  // namespace

void add_plot_command(CLI::App& app, Action& action) {
  auto o = std::make_shared<PlotOptions>();
  o->common.out = "out/plot";
  CLI::App* command = app.add_subcommand(
      "plot", "Figures of push runs: F(u), heave, the resistance by face, sections through the sleeper");
  command->add_option("runs", o->runs, "Push folders (holding push.h5; the first is the sections' reference)")
      ->required();
  command->add_option("--labels", o->labels, "One label per folder (default: the folders)");
  command->add_option("--title", o->title, "The figures' title (default: the first folder's name)");
  add_common_options(*command, o->common);
  command->footer(
      "Writes OUT/figures.h5 (the numbers) and OUT/figures/{force_displacement, resistance_by_face,\n"
      "displacement_section, force_chains}.png and .svg, drawn by studies/python/mfdem/push_figures.py.");
  command->callback([o, &action] {
    action = [o] {
      if (o->common.seed_given)
        throw config::ConfigError(fmt::format("--seed {}: plot draws finished runs", o->common.seed));
      return plot(*o);
    };
  });
}

}  // namespace mfdem::cli
