// `mfdem stats`: repeated stochastic packings of one model, with intervals, the seeds a width
// needs, and a cheap model as a control variate (studies/campaigns/stats.hpp).
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <atomic>
#include <filesystem>
#include <iostream>
#include <memory>

#include "studies/campaigns/compare.hpp"
#include "studies/campaigns/stats.hpp"
#include "studies/cli/campaign_runs.hpp"
#include "studies/cli/campaign_share.hpp"
#include "studies/cli/campaign_workers.hpp"
#include "studies/cli/periodic_report.hpp"
#include "studies/cli/common_options.hpp"
#include "studies/cli/python_figures.hpp"
#include "studies/cli/subcommands.hpp"
#include "studies/cli/version.hpp"
#include "studies/config/config_error.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::cli {
namespace {

namespace fs = std::filesystem;

struct StatsOptions {
  CommonOptions common;
  std::string config;
  std::string model = "all-clump";
  std::string seeds = "1-5";
  double until_width = 0.0;   // %
  std::string width_output = "peak_force";
  std::size_t max_seeds = 30;
  double report_width = 2.0;  // %
  std::string control;
  std::string control_seeds;
  std::size_t resamples = 10000;
  bool figures = true;
  std::string slice;  // K/N: this process's share (a job array's task)
  int jobs = 1;
  bool worker = false;  // a process of --jobs: computes its slice, writes no tables
};

// This command line again, for the workers of --jobs (without --slice and --jobs).
std::vector<std::string> worker_args(const StatsOptions& o) {
  std::vector<std::string> args = {"stats", o.config, "--model", o.model, "--seeds", o.seeds, "--threads",
                                   std::to_string(o.common.threads), "--out", o.common.out.string()};
  if (!o.control.empty()) args.insert(args.end(), {"--control", o.control, "--control-seeds", o.control_seeds});
  return args;
}

campaigns::StatsRequest make_request(const StatsOptions& o, const CampaignShare& share) {
  campaigns::StatsRequest r;
  r.config = railway::load_push_config(o.config);
  r.model = campaigns::parse_model(o.model, "--model");
  r.seeds = campaigns::parse_seeds(o.seeds, "--seeds");
  r.until_width = o.until_width / 100.0;
  r.width_output = o.width_output;
  r.max_seeds = o.max_seeds;
  r.report_width = o.report_width / 100.0;
  if (!o.control.empty()) r.control = campaigns::parse_model(o.control, "--control");
  if (!o.control_seeds.empty()) r.control_seeds = campaigns::parse_seeds(o.control_seeds, "--control-seeds");
  r.bootstrap.resamples = o.resamples;
  r.slice = share.slice;
  campaigns::check_stats_request(r);
  return r;
}

int stats(StatsOptions o) {
  const CampaignShare share = campaign_share(o.slice, o.jobs);
  if (o.jobs > 1 && o.until_width > 0.0)
    throw config::ConfigError(fmt::format("--jobs {}: --until-width adds one seed at a time from the runs before it; "
                                          "run it with --jobs 1", o.jobs));
  campaigns::StatsRequest request = make_request(o, share);  // every input checked before any work
  if (!share.writes_tables() || o.worker) o.common.quiet = true;
  runs::RunStore store(o.common.out);
  if (const int cleared = store.clear_abandoned(); cleared > 0 && !o.common.quiet)
    fmt::print(std::cerr, "cleared {} runs in progress left by stopped processes\n", cleared);
  campaigns::RunContext context;
  context.revision = git_revision();
  const std::size_t planned = (request.until_width > 0.0 ? request.max_seeds : request.seeds.size()) +
                              request.control_seeds.size();
  if (!o.common.quiet)
    fmt::print(std::cerr, "stats: {} on {}, seeds {}{}{}; runs in {}\n", request.model.text(request.config),
               request.config.name, o.seeds,
               request.until_width > 0.0 ? fmt::format(", until +-{:g} % on {} (at most {} seeds)", o.until_width,
                                                       o.width_output, o.max_seeds)
                                         : "",
               request.control ? fmt::format("; control variate {} on seeds {}", request.control->text(request.config),
                                             o.control_seeds)
                               : "",
               o.common.out.string());
  // The ETA counts runs; with --until-width the plan is the budget, an upper bound.
  scene::Progress progress("stats", double(planned), o.common.quiet);
  std::vector<std::uint64_t> seeds;
  {
    std::atomic<std::size_t> done{0};
    PeriodicReport report([&] {
      progress.update(double(done), campaign_progress_detail(store, fmt::format("{} runs made or found", done.load())));
    }, !o.common.quiet);
    run_with_jobs(o.jobs, worker_args(o), o.common.out, share.slice, [&](const campaigns::RunSlice& slice) {
      request.slice = slice;
      seeds = campaigns::run_stats(
          store, request,
          [&](const campaigns::Model& model, std::uint64_t seed) {
            campaigns::ensure_push_run(store, request.config, model, seed, context);
          },
          [&](std::size_t made, std::size_t) {
            done = made;
            report.now();
          });
    }, [&] { report.now(); });
  }
  progress.finish();
  if (share.mpi) wait_for_all_ranks();
  if (!share.writes_tables() || o.worker) return 0;
  std::size_t missing = 0;
  for (auto seed : request.seeds) missing += store.has(campaigns::run_key(request.config, request.model, seed)) ? 0 : 1;
  for (auto seed : request.control_seeds)
    missing += store.has(campaigns::run_key(request.config, *request.control, seed)) ? 0 : 1;
  if (other_slices_pending(share, missing, "stats")) return 0;
  store.write_index();
  const campaigns::StatsTable table = campaigns::stats_table(store, request, seeds);
  const fs::path markdown = o.common.out / "stats.md", csv = o.common.out / "stats.csv";
  write_report(markdown, true, [&](std::ostream& out) { campaigns::write_stats_markdown(out, table); });
  campaigns::write_stats_csv(csv, table);
  if (!o.common.quiet) {
    campaigns::print_stats_table(std::cout, table);
    fmt::print("  written: {}, {}, {}\n", markdown.string(), csv.string(), (o.common.out / "index.csv").string());
  }
  if (o.figures && table.finished > 0) {
    campaigns::write_stats_figure_data(o.common.out / "stats.h5", store, request, table);
    draw_study_figures("stats_figures", o.common.out.string(), o.common.quiet);
  }
  return table.finished > 0 ? 0 : 1;
}

}  // namespace

void add_stats_command(CLI::App& app, Action& action) {
  auto o = std::make_shared<StatsOptions>();
  o->common.out = "out/stats";
  o->common.threads = 0;
  CLI::App* command = app.add_subcommand(
      "stats", "Repeated stochastic packings of one model: intervals, the seeds a width needs, a control variate");
  command->add_option("config", o->config, "A preset (mini, study, standard, paper) or a study config file")->required();
  command->add_option("--model", o->model,
                      "The model: a policy NAME[:k=v,...] (all-clump, all-ball, layer-by-height:h_fraction=F, "
                      "zone-by-distance:d=M), optionally with mu_r= and ball_mu=")
      ->capture_default_str();
  command->add_option("--seeds", o->seeds, "Seeds (packings): 1-10, 1,3,7 or 2-4,9")->capture_default_str();
  command->add_option("--until-width", o->until_width,
                      "Add seeds until the 95 % interval of --width-output is +- this % of its mean (0: off)")
      ->check(CLI::Range(0.0, 99.0))
      ->capture_default_str();
  command->add_option("--width-output", o->width_output, "The output --until-width watches")
      ->check(CLI::IsMember({"peak_force", "max_contact_force", "contact_force_q999", "mean_force"}))
      ->capture_default_str();
  command->add_option("--max-seeds", o->max_seeds, "The budget of --until-width: seeds run in all, at most")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000}))
      ->capture_default_str();
  command->add_option("--report-width", o->report_width,
                      "The interval width (+- %) whose seed count the table gives (--until-width's when set)")
      ->check(CLI::Range(0.01, 99.0))
      ->capture_default_str();
  command->add_option("--control", o->control,
                      "A cheaper model of the same config as a control variate for the model's mean (e.g. all-ball)");
  command->add_option("--control-seeds", o->control_seeds,
                      "The control model's seeds: every seed of --seeds and more (e.g. --seeds 1-5 --control-seeds 1-20)");
  command->add_option("--resamples", o->resamples, "Bootstrap resamples")
      ->check(CLI::Range(std::size_t{100}, std::size_t{10000000}))
      ->capture_default_str();
  command->add_flag("!--no-figures", o->figures, "Write the tables only (no stats.h5, no PNG/SVG)");
  add_slice_option(*command, o->slice);
  add_jobs_options(*command, o->jobs, o->worker);
  add_common_options(*command, o->common);
  command->footer(
      "Each seed is its own packing (deposition); every run is a folder OUT/runs/KEY of the run store that\n"
      "compare and calibrate share, so the same command again computes only what is missing. Writes\n"
      "OUT/stats.md, OUT/stats.csv, OUT/index.csv and the figures (OUT/figures/*.png and .svg, drawn from\n"
      "OUT/stats.h5 by studies/python/mfdem/stats_figures.py; docs/stats.md).");
  command->callback([o, &action] {
    action = [o] {
      refuse_single_seed(o->common, "stats");
      apply_thread_count(o->common);
      return stats(*o);
    };
  });
}

}  // namespace mfdem::cli
