// `mfdem compare`: models on the same beds, the trade table over seeds (studies/campaigns/compare.hpp).
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>

#include "studies/campaigns/compare.hpp"
#include "studies/campaigns/compare_figures.hpp"
#include "studies/campaigns/run_costs.hpp"
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

constexpr const char* kDefaultModels =
    "all-clump,layer-by-height:h_fraction=0.5,zone-by-distance:d=0.03,all-ball";

struct CompareOptions {
  CommonOptions common;
  std::string config;
  std::string models = kDefaultModels;
  std::string seeds = "1-3";
  std::string reference;
  int jobs = 2;
  double tolerance = 5.0;  // %
  bool retry_failed = false;
  bool figures = true;
  int worker = 0;          // > 0: the k-th process of --jobs: runs, prints no table
  bool jobs_given = false;
  std::string slice;       // K/N: this process's share (a job array's task)
};

campaigns::CompareRequest make_request(const CompareOptions& o) {
  campaigns::CompareRequest request;
  request.config = railway::load_push_config(o.config);
  request.models = campaigns::parse_models(o.models, "--models");
  request.seeds = campaigns::parse_seeds(o.seeds, "--seeds");
  request.tolerance = o.tolerance / 100.0;
  if (!o.reference.empty()) {
    const auto given = campaigns::parse_models(o.reference, "--reference");
    const std::string wanted = given.front().text(request.config);
    request.reference = request.models.size();
    for (std::size_t m = 0; m < request.models.size(); ++m)
      if (request.models[m].text(request.config) == wanted) request.reference = m;
    if (request.reference == request.models.size())
      throw config::ConfigError(fmt::format("--reference {}: not one of the --models ({})", o.reference, o.models));
  }
  for (std::size_t a = 0; a < request.models.size(); ++a)
    for (std::size_t b = a + 1; b < request.models.size(); ++b)
      if (request.models[a].text(request.config) == request.models[b].text(request.config))
        throw config::ConfigError(fmt::format("--models {}: '{}' is given twice", o.models,
                                              request.models[a].text(request.config)));
  return request;
}

// The other processes of --jobs: this command again, one job each, writing into the same store.
// Each starts at another seed and skips runs another process holds (the store's claims).
std::vector<pid_t> spawn_workers(const CompareOptions& o, int count) {
  std::vector<pid_t> workers;
  for (int k = 0; k < count; ++k) {
    const std::vector<std::string> args = {"compare", o.config, "--models", o.models, "--seeds", o.seeds,
                                           "--out", o.common.out.string(), "--jobs", "1", "--threads",
                                           std::to_string(o.common.threads), "--worker", std::to_string(k + 1),
                                           "--quiet"};
    workers.push_back(spawn_worker(args, o.common.out / "logs" / fmt::format("worker-{}.log", k + 1), k + 1));
  }
  return workers;
}

int compare(CompareOptions o) {
  const campaigns::CompareRequest request = make_request(o);  // every input checked before any work
  const CampaignShare share = campaign_share(o.slice, o.jobs_given ? o.jobs : 1);
  if (!share.slice.whole()) o.jobs = 1;
  if (!share.writes_tables()) o.common.quiet = true;
  runs::RunStore store(o.common.out);
  const int total = static_cast<int>(request.seeds.size() * request.models.size());
  campaigns::RunContext context;
  context.revision = git_revision();
  if (o.worker > 0) {
    campaigns::run_compare(store, request, context, {}, static_cast<std::size_t>(o.worker - 1));
    return 0;
  }
  if (const int cleared = store.clear_abandoned(); cleared > 0 && !o.common.quiet)
    fmt::print(std::cerr, "cleared {} runs in progress left by stopped processes\n", cleared);
  const std::vector<std::string> keys = campaigns::run_keys(request);
  if (o.retry_failed)
    for (const auto& key : keys)
      if (const auto record = store.find(key); record && !record->finished()) store.forget(key);
  const auto done_in_store = [&] { return static_cast<int>(store.count_published(keys)); };
  // The ETA weighs each missing run by its model's wall in the store's finished runs (models
  // differ by a factor of three); a store without any counts runs.
  const campaigns::RunCosts costs = campaigns::expected_run_costs(store, request);
  const std::vector<std::size_t>& missing_runs = costs.missing_runs;
  const int done_before = total - static_cast<int>(missing_runs.size());
  if (!o.common.quiet) {
    fmt::print(std::cerr, "compare: {} models x {} seeds = {} runs, {} already in {}; {} job{} of {} thread{}\n",
               request.models.size(), request.seeds.size(), total, done_before, o.common.out.string(), o.jobs,
               o.jobs > 1 ? "s" : "", o.common.threads, o.common.threads > 1 ? "s" : "");
    if (costs.measured && !missing_runs.empty())
      fmt::print(std::cerr, "  expected: about {} with {} job{} (the walls of the finished runs of each model)\n",
                 scene::format_duration(costs.missing / std::min<double>(o.jobs, double(missing_runs.size()))), o.jobs,
                 o.jobs > 1 ? "s" : "");
  }
  scene::Progress progress("compare", costs.missing, o.common.quiet);
  {
    // Polled every second while workers run: folder lookups of the missing runs, no record read.
    PeriodicReport report([&] {
      int done = done_before;
      double done_cost = 0.0;
      for (std::size_t k : missing_runs)
        if (store.has(keys[k])) done_cost += costs.seconds[k], ++done;
      progress.update(done_cost, campaign_progress_detail(store, fmt::format("{} of {} runs in the store", done, total)));
    }, !o.common.quiet);
    if (o.jobs > 1 && done_before < total)
      wait_for_workers(spawn_workers(o, std::min(o.jobs, total - done_before)), [&] { report.now(); });
    // This process then (or alone) runs whatever is left: a worker's run that failed to start.
    campaigns::run_compare(store, request, context, [&] { report.now(); }, 0, share.slice);
  }
  progress.finish();
  if (share.mpi) wait_for_all_ranks();
  if (!share.writes_tables()) return 0;
  if (other_slices_pending(share, static_cast<std::size_t>(total - done_in_store()), "compare")) return 0;
  store.write_index();
  const campaigns::CompareTable table = campaigns::compare_table(store, request);
  const fs::path markdown = o.common.out / "compare.md", csv = o.common.out / "compare.csv";
  campaigns::write_compare_markdown(markdown, table);
  campaigns::write_compare_csv(csv, table);
  if (!o.common.quiet) {
    campaigns::print_compare_table(std::cout, table);
    fmt::print("  written: {}, {}, {}\n", markdown.string(), csv.string(), (o.common.out / "index.csv").string());
  }
  if (o.figures) {
    const fs::path data = o.common.out / "figures.h5";
    if (campaigns::write_compare_figure_data(data, store, request)) {
      draw_study_figures("compare_figures", o.common.out.string(), o.common.quiet);
    } else {
      fmt::print(std::cerr, "mfdem: no figures: the reference has no finished run\n");
    }
  }
  const int missing = total - done_in_store();
  if (missing > 0)
    fmt::print(std::cerr, "mfdem: {} runs are still being computed by other processes; run the same command again "
                          "to complete the table\n", missing);
  return 0;
}

}  // namespace

void add_compare_command(CLI::App& app, Action& action) {
  auto o = std::make_shared<CompareOptions>();
  o->common.out = "out/compare";
  o->common.threads = 1;
  CLI::App* command = app.add_subcommand(
      "compare", "Run models on the same beds over seeds and tabulate what each saved and what it cost");
  command->add_option("config", o->config, "A preset (mini, study, standard, paper) or a study config file")->required();
  command->add_option("--models", o->models,
                      "Models, the first the reference: policies NAME[:k=v,...] (all-clump, all-ball, "
                      "layer-by-height:h=M or h_fraction=F, zone-by-distance:d=M), each optionally with mu_r= "
                      "and ball_mu= for its balls; separated by ',' (or ';')")
      ->capture_default_str();
  command->add_option("--seeds", o->seeds, "Seeds: 1-5, 1,3,7 or 2-4,9")->capture_default_str();
  command->add_option("--reference", o->reference, "The model the others are compared with (default: the first)");
  CLI::Option* jobs = command->add_option("--jobs", o->jobs, "Runs computed at once, each a process of --threads threads")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  command->add_option("--tolerance", o->tolerance, "The verdict's tolerance on both outputs, %")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  command->add_flag("--retry-failed", o->retry_failed, "Compute the runs recorded as failed again");
  command->add_flag("!--no-figures", o->figures, "Write the tables only (no figures.h5, no PNG/SVG)");
  add_slice_option(*command, o->slice);
  command->add_option("--worker", o->worker)->group("");  // a process of --jobs
  add_common_options(*command, o->common);
  command->footer(
      "Every model of a seed starts from the same deposited bed (made once, kept in OUT/shared/), so the\n"
      "differences are paired by seed. Each run is a folder OUT/runs/KEY (push.h5, push_summary.toml,\n"
      "packing.h5, run.toml); the same command again computes only what is missing. Writes\n"
      "OUT/compare.md, OUT/compare.csv and OUT/index.csv, and the figures (OUT/figures/*.png and .svg,\n"
      "drawn from OUT/figures.h5 by studies/python/mfdem/compare_figures.py; docs/compare.md).");
  command->callback([o, jobs, &action] {
    action = [o, jobs] {
      refuse_single_seed(o->common, "compare");
      apply_thread_count(o->common);
      o->jobs_given = jobs->count() > 0;
      return compare(*o);
    };
  });
}

}  // namespace mfdem::cli
