// `mfdem calibrate`: the ball layer fitted to the all-clump reference (studies/campaigns/calibrate.hpp).
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "studies/campaigns/calibrate.hpp"
#include "studies/campaigns/calibrate_figures.hpp"
#include "studies/campaigns/calibrate_report.hpp"
#include "studies/campaigns/compare.hpp"
#include "studies/cli/common_options.hpp"
#include "studies/cli/python_figures.hpp"
#include "studies/cli/campaign_runs.hpp"
#include "studies/cli/campaign_share.hpp"
#include "studies/cli/subcommands.hpp"
#include "studies/config/config_error.hpp"

namespace mfdem::cli {
namespace {

namespace fs = std::filesystem;

struct CalibrateOptions {
  CommonOptions common;
  std::string config;
  std::string policy = "layer-by-height";
  std::string parameters = "mu_r=0:0.6,h_fraction=0.3:0.9";
  std::string seeds = "1-3";
  std::string verify_seeds = "4-5";
  std::string reference;
  std::string reference_model = "all-clump";
  std::string contact = "max";
  std::string cheap;
  std::string cheap_seeds;
  std::optional<double> cheap_cost;
  double budget = 20.0;
  int initial = 0, initial_cheap = 0;
  int batch = 1;
  double shortest_length = 0.1;
  bool figures = true;
};

// "peak=12030,contact=2180" in N.
std::array<double, 2> parse_reference(const std::string& text) {
  std::array<double, 2> value{NAN, NAN};
  std::stringstream entries(text);
  for (std::string entry; std::getline(entries, entry, ',');) {
    const auto equals = entry.find('=');
    const std::string name = entry.substr(0, equals);
    double v = NAN;
    try {
      v = std::stod(entry.substr(equals + 1));
    } catch (const std::exception&) {
    }
    if (equals == std::string::npos || !(v > 0.0) || !std::isfinite(v) || (name != "peak" && name != "contact"))
      throw config::ConfigError(fmt::format("--reference {}: expected peak=N,contact=N (forces in N, > 0)", text));
    value[name == "peak" ? 0 : 1] = v;
  }
  if (!std::isfinite(value[0]) || !std::isfinite(value[1]))
    throw config::ConfigError(fmt::format("--reference {}: both peak= and contact= are needed", text));
  return value;
}

int calibrate(const CalibrateOptions& o) {
  // Every input checked before any work.
  const railway::PushStudyConfig config = railway::load_push_config(o.config);
  std::optional<railway::PushStudyConfig> cheap;
  if (!o.cheap.empty()) cheap = railway::load_push_config(o.cheap);
  campaigns::CalibrateRequest request;
  request.policy = o.policy;
  request.parameters = campaigns::parse_calibration_parameters(o.parameters, o.policy, config, "--parameters");
  request.seeds = campaigns::parse_seeds(o.seeds, "--seeds");
  if (o.verify_seeds != "none") request.verify_seeds = campaigns::parse_seeds(o.verify_seeds, "--verify-seeds");
  for (auto s : request.verify_seeds)
    for (auto t : request.seeds)
      if (s == t)
        throw config::ConfigError(fmt::format("--verify-seeds {}: seed {} is also a fitting seed (--seeds {}); the check "
                                              "needs fresh ones", o.verify_seeds, s, o.seeds));
  if (!o.reference.empty()) request.reference = parse_reference(o.reference);
  request.reference_model = campaigns::parse_model(o.reference_model, "--reference-model");
  request.contact_quantile = o.contact == "q999";
  request.budget = o.budget;
  request.batch = o.batch;
  request.shortest_length = o.shortest_length;
  if (!o.cheap_seeds.empty()) {
    request.cheap_seeds = campaigns::parse_seeds(o.cheap_seeds, "--cheap-seeds");
    request.cheap_on_same_config = !cheap.has_value();
    if (request.cheap_on_same_config && request.cheap_seeds.size() >= request.seeds.size())
      throw config::ConfigError(fmt::format("--cheap-seeds {}: without --cheap the cheap level is the same config on "
                                            "fewer seeds; expected fewer than the {} of --seeds {}",
                                            o.cheap_seeds, request.seeds.size(), o.seeds));
  }
  request.two_levels = cheap.has_value() || !request.cheap_seeds.empty();
  const auto refuse_without_cheap_level = [&](const char* option, double value) {
    if (!request.two_levels)
      throw config::ConfigError(
          fmt::format("{} {:g}: there is no cheap level (give --cheap or --cheap-seeds)", option, value));
  };
  if (o.cheap_cost) refuse_without_cheap_level("--cheap-cost", *o.cheap_cost);
  // Fewer seeds of the same runs cost in proportion; another config's runs cost what the user says.
  request.cheap_cost = o.cheap_cost.value_or(request.cheap_on_same_config
                                                 ? double(request.cheap_seeds.size()) / double(request.seeds.size())
                                                 : 0.25);
  request.initial_expensive = o.initial;
  request.initial_cheap = o.initial_cheap;
  if (o.initial_cheap > 0) refuse_without_cheap_level("--initial-cheap", o.initial_cheap);
  request.design_seed = o.common.seed;
  fs::create_directories(o.common.out);
  request.record = o.common.out / "calibration_record.csv";

  CampaignRuns runs(o.common.out, config, cheap, request.contact_quantile, o.common.quiet);
  if (!o.common.quiet)
    fmt::print(std::cerr, "calibrate {} on {}: {} over seeds {}, budget {} candidates; runs in {}\n", o.parameters,
               config.name, o.policy, o.seeds, o.budget, o.common.out.string());
  const campaigns::CalibrateResult result = campaigns::run_calibration(runs.runner, request);
  runs.store.write_index();
  const std::string title = fmt::format("mfdem calibrate {} --policy {} --parameters {}", o.config, o.policy, o.parameters);
  const fs::path markdown = o.common.out / "calibrate.md", csv = o.common.out / "calibrate.csv";
  write_report(markdown, o.common.quiet,
               [&](std::ostream& out) { campaigns::write_calibration_markdown(out, title, request, result); });
  campaigns::write_calibration_csv(csv, request, result);
  if (!o.common.quiet)
    fmt::print("  written: {}, {}, {}\n", markdown.string(), csv.string(), request.record.string());
  if (o.figures) {
    campaigns::write_calibration_figure_data(o.common.out / "calibration.h5", config.name, request, result);
    draw_study_figures("calibrate_figures", o.common.out.string(), o.common.quiet);
  }
  return 0;
}

}  // namespace

void add_calibrate_command(CLI::App& app, Action& action) {
  auto o = std::make_shared<CalibrateOptions>();
  o->common.out = "out/calibrate";
  o->common.threads = 0;
  CLI::App* command = app.add_subcommand(
      "calibrate", "Fit the ball layer (rolling friction, layer height) to the all-clump reference");
  command->add_option("config", o->config, "A preset (mini, study, standard, paper) or a study config file")->required();
  command->add_option("--policy", o->policy, "layer-by-height or zone-by-distance (fixed parameters may follow: "
                                             "layer-by-height:h_fraction=0.5)")->capture_default_str();
  command->add_option("--parameters", o->parameters,
                      "What to fit and its range, NAME=LOWER:UPPER,...: mu_r, ball_mu, h, h_fraction, d; the lowest "
                      "layer height (the largest zone distance) is the smallest saving accepted")
      ->capture_default_str();
  command->add_option("--seeds", o->seeds, "Seeds every candidate runs on (paired)")->capture_default_str();
  command->add_option("--verify-seeds", o->verify_seeds, "Fresh seeds for the check at the calibrated point, or none")
      ->capture_default_str();
  command->add_option("--reference", o->reference,
                      "Targets given as peak=N,contact=N instead of all-clump runs (e.g. the paper's peak=12030,contact=2180)");
  command->add_option("--reference-model", o->reference_model,
                      "The model whose runs on the same seeds are the targets: all-clump, or a multi-layer model at "
                      "known parameters (layer-by-height:h_fraction=0.5,mu_r=0.2) to check that a calibration finds them")
      ->capture_default_str();
  command->add_option("--contact", o->contact, "The contact force matched: max, or q999 (its 99.9 % quantile, less noisy)")
      ->check(CLI::IsMember({"max", "q999"}))
      ->capture_default_str();
  command->add_option("--cheap", o->cheap, "A cheaper config (e.g. mini) as the co-kriging's cheap level");
  command->add_option("--cheap-seeds", o->cheap_seeds,
                      "The cheap level's seeds: with --cheap, its seeds (default: --seeds); alone, a cheap level of "
                      "the same config on fewer seeds (e.g. --seeds 1-3 --cheap-seeds 1)");
  command->add_option("--cheap-cost", o->cheap_cost,
                      "A cheap candidate's cost in expensive ones (default: 0.25 with --cheap; the share of the "
                      "seeds with --cheap-seeds alone)")
      ->check(CLI::Range(0.001, 0.999));
  command->add_option("--budget", o->budget, "Candidates to spend at most (initial design included)")
      ->check(CLI::Range(2.0, 1e4))
      ->capture_default_str();
  command->add_option("--initial", o->initial,
                      "Expensive candidates of the initial design (0: 2 d + 2 for d parameters); the first ones of "
                      "the cheap design when there is a cheap level")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  command->add_option("--initial-cheap", o->initial_cheap, "Cheap candidates of the initial design (0: 3 x --initial)")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  command->add_option("--batch", o->batch, "Candidates proposed at once")->check(CLI::Range(1, 64))->capture_default_str();
  command->add_option("--shortest-length", o->shortest_length,
                      "The surrogates' shortest length scale, as a fraction of each range (DEM scatter is noise, "
                      "not structure)")
      ->check(CLI::Range(1e-3, 1.0))
      ->capture_default_str();
  command->add_flag("!--no-figures", o->figures, "Write the tables only (no calibration.h5, no PNG/SVG)");
  add_common_options(*command, o->common);
  command->footer(
      "Each candidate runs on every --seeds seed from the seed's deposited bed (made once, kept in OUT/shared/);\n"
      "its outputs are the means over the seeds. The surrogates of both outputs, expected improvement and the\n"
      "posterior are calibration/'s (calibration/README.md). Every DEM run is a folder OUT/runs/KEY and every\n"
      "candidate a line of OUT/calibration_record.csv: the same command again recomputes nothing finished.\n"
      "Writes OUT/calibrate.md (table, verification on --verify-seeds, cost, convergence), OUT/calibrate.csv and\n"
      "the figures OUT/figures/{misfit_surface, posterior, convergence}.png/.svg (from OUT/calibration.h5).\n"
      "--seed sets the initial design's shift.");
  command->callback([o, &action] {
    action = [o] {
      apply_thread_count(o->common);
      require_one_process("calibrate");
      return calibrate(*o);
    };
  });
}

}  // namespace mfdem::cli
