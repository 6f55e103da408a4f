// `mfdem optimise-layer`: the cheapest ball layer whose calibrated error stays within a tolerance
// (studies/campaigns/optimise_layer.hpp).
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "studies/campaigns/compare.hpp"
#include "studies/campaigns/optimise_layer.hpp"
#include "studies/campaigns/optimise_layer_report.hpp"
#include "studies/cli/common_options.hpp"
#include "studies/cli/python_figures.hpp"
#include "studies/cli/campaign_runs.hpp"
#include "studies/cli/campaign_share.hpp"
#include "studies/cli/subcommands.hpp"
#include "studies/config/config_error.hpp"

namespace mfdem::cli {
namespace {

namespace fs = std::filesystem;

struct OptimiseOptions {
  CommonOptions common;
  std::string config;
  std::vector<std::string> families = {"layer-by-height:h_fraction=0.3:0.9"};
  std::string friction = "0:0.6";
  std::string seeds = "1-3";
  std::string reference_model = "all-clump";
  std::string contact = "max";
  double tolerance = 5.0;  // %
  int initial = 6, runs_per_extent = 3, max_extents = 6;
  std::string uncalibrated = "layer-by-height:h_fraction=0.5";
  double shortest_length = 0.1;
  bool figures = true;
};

// "layer-by-height:h_fraction=0.3:0.9" -> the policy and its extent's range.
std::pair<std::string, campaigns::CalibrationParameter> parse_family(const std::string& text,
                                                                     const railway::PushStudyConfig& config) {
  const auto colon = text.find(':');
  if (colon == std::string::npos)
    throw config::ConfigError(fmt::format("--family {}: expected POLICY:EXTENT=LOWER:UPPER (e.g. "
                                          "layer-by-height:h_fraction=0.3:0.9 or zone-by-distance:d=0.02:0.15)", text));
  const std::string policy = text.substr(0, colon);
  const auto parameters = campaigns::parse_calibration_parameters(text.substr(colon + 1), policy, config, "--family", "--family");
  if (parameters.size() != 1 || parameters[0].name == "mu_r" || parameters[0].name == "ball_mu")
    throw config::ConfigError(fmt::format("--family {}: one extent expected (h or h_fraction for layer-by-height, d for "
                                          "zone-by-distance); mu_r's range is --mu-r", text));
  return {policy, parameters[0]};
}

int optimise(const OptimiseOptions& o) {
  // Every input checked before any work.
  const railway::PushStudyConfig config = railway::load_push_config(o.config);
  campaigns::OptimiseLayerRequest base;
  base.seeds = campaigns::parse_seeds(o.seeds, "--seeds");
  if (base.seeds.size() < 2)
    throw config::ConfigError(fmt::format("--seeds {}: at least two seeds (the tolerance is judged against their "
                                          "spread)", o.seeds));
  base.friction = campaigns::parse_calibration_parameters("mu_r=" + o.friction, "layer-by-height", config, "--mu-r")[0];
  base.reference_model = campaigns::parse_model(o.reference_model, "--reference-model");
  base.contact_quantile = o.contact == "q999";
  base.tolerance = o.tolerance / 100.0;
  base.initial = o.initial, base.runs_per_extent = o.runs_per_extent, base.max_extents = o.max_extents;
  base.shortest_length = o.shortest_length;
  std::vector<campaigns::OptimiseLayerRequest> requests;
  for (const auto& text : o.families) {
    auto r = base;
    std::tie(r.policy, r.extent) = parse_family(text, config);
    requests.push_back(r);
  }
  const std::vector<campaigns::Model> uncalibrated =
      o.uncalibrated == "none" ? std::vector<campaigns::Model>{} : campaigns::parse_models(o.uncalibrated, "--uncalibrated");

  CampaignRuns runs(o.common.out, config, std::nullopt, base.contact_quantile, o.common.quiet);

  std::vector<campaigns::FamilyFront> fronts;
  for (const auto& r : requests) {
    if (!o.common.quiet)
      fmt::print(std::cerr, "optimise-layer {} on {}: {} from {:g} to {:g}, mu_r {:g}-{:g}, seeds {}; runs in {}\n",
                 r.policy, config.name, r.extent.name, r.extent.lower, r.extent.upper, r.friction.lower,
                 r.friction.upper, o.seeds, o.common.out.string());
    fronts.push_back({r.policy, r.extent.name, campaigns::optimise_layer(runs.runner, r)});
  }
  std::vector<campaigns::MeasuredModel> measured;
  for (const auto& m : uncalibrated) {
    std::vector<campaigns::RunOutputs> per_seed;
    for (auto seed : base.seeds) per_seed.push_back(runs.runner.run(m, seed, calibration::Level::expensive));
    measured.push_back({m.text(config), campaigns::measure_candidate(per_seed, fronts.front().result.reference_runs,
                                                                     base.tolerance)});
  }
  runs.store.write_index();

  std::string families;
  for (const auto& f : o.families) families += (families.empty() ? "" : " --family ") + f;
  const std::string title = fmt::format("mfdem optimise-layer {} --family {}", o.config, families);
  const fs::path markdown = o.common.out / "optimise_layer.md", csv = o.common.out / "optimise_layer.csv";
  write_report(markdown, o.common.quiet,
               [&](std::ostream& out) { campaigns::write_optimise_markdown(out, title, base, fronts, measured); });
  campaigns::write_optimise_csv(csv, fronts, measured);
  {
    std::ofstream labels(o.common.out / "optimise_layer.toml");
    fmt::print(labels, "config = \"{}\"\nseeds = {}\ntolerance = {:.17g}\ncontact_quantile = {}\n", config.name,
               base.seeds.size(), base.tolerance, base.contact_quantile ? "true" : "false");
  }
  if (!o.common.quiet) fmt::print("  written: {}, {}\n", markdown.string(), csv.string());
  if (o.figures) draw_study_figures("optimise_figures", o.common.out.string(), o.common.quiet);
  return 0;
}

}  // namespace

void add_optimise_layer_command(CLI::App& app, Action& action) {
  auto o = std::make_shared<OptimiseOptions>();
  o->common.out = "out/optimise_layer";
  o->common.threads = 0;
  CLI::App* command = app.add_subcommand(
      "optimise-layer", "The cheapest ball layer (or zone) whose calibrated error stays within a tolerance");
  command->add_option("config", o->config, "A preset (mini, study, standard, paper) or a study config file")->required();
  command->add_option("--family", o->families,
                      "A policy and its extent's range, POLICY:EXTENT=LOWER:UPPER; give it twice to set "
                      "layer-by-height against zone-by-distance on one front")
      ->capture_default_str();
  command->add_option("--mu-r", o->friction, "The range mu_r is calibrated in at each extent, LOWER:UPPER")
      ->capture_default_str();
  command->add_option("--seeds", o->seeds, "Seeds every candidate runs on (paired; two at least)")->capture_default_str();
  command->add_option("--reference-model", o->reference_model, "The model matched")->capture_default_str();
  command->add_option("--contact", o->contact, "The contact force matched: max, or q999 (its 99.9 % quantile)")
      ->check(CLI::IsMember({"max", "q999"}))
      ->capture_default_str();
  command->add_option("--tolerance", o->tolerance,
                      "On both relative errors, in %; never judged finer than twice their standard error over the seeds")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  command->add_option("--initial", o->initial, "Runs of the shared design over (mu_r, extent)")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  command->add_option("--runs-per-extent", o->runs_per_extent, "Runs to calibrate mu_r at one extent, at most")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  command->add_option("--max-extents", o->max_extents, "Extents evaluated per family, at most (the two ends included)")
      ->check(CLI::Range(2, 100))
      ->capture_default_str();
  command->add_option("--uncalibrated", o->uncalibrated,
                      "Models measured as they are, for scale on the front (the config's mu_r unless given), or none")
      ->capture_default_str();
  command->add_option("--shortest-length", o->shortest_length,
                      "The surrogate's shortest length scale, as a fraction of each range")
      ->check(CLI::Range(1e-3, 1.0))
      ->capture_default_str();
  command->add_flag("!--no-figures", o->figures, "Write the tables only (no PNG/SVG)");
  add_common_options(*command, o->common);
  command->footer(
      "One surrogate of both outputs over (mu_r, extent) is fitted on every run; at each extent mu_r is its\n"
      "predicted best, run and refitted until it settles; the extent is bisected between the dearest end and the\n"
      "cheapest on the measured paired errors. Every DEM run is a folder OUT/runs/KEY (the run store of compare\n"
      "and calibrate): the same command again recomputes nothing. Writes OUT/optimise_layer.md (printed),\n"
      "OUT/optimise_layer.csv and OUT/figures/front.png/.svg.");
  command->callback([o, &action] {
    action = [o] {
      apply_thread_count(o->common);
      require_one_process("optimise-layer");
      return optimise(*o);
    };
  });
}

}  // namespace mfdem::cli
