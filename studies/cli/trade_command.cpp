// `mfdem trade`: what the numerical knobs buy and where stability ends (studies/campaigns/trade.hpp).
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "studies/campaigns/trade.hpp"
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

struct TradeOptions {
  CommonOptions common;
  std::string config;
  std::string model = "all-clump";
  std::vector<std::string> knobs;
  std::string seeds = "1-3";
  double tolerance = 5.0;  // %
  std::string slice;
  int jobs = 1;
  bool worker = false;  // a process of --jobs: computes its slice, writes no tables
  bool figures = true;
  fs::path compare_study;  // an `mfdem compare` folder whose models the figure sets beside the knobs
};

// This command line again, for the workers of --jobs (without --slice and --jobs).
std::vector<std::string> worker_args(const TradeOptions& o) {
  std::vector<std::string> args = {"trade", o.config, "--model", o.model, "--seeds", o.seeds, "--tolerance",
                                   fmt::format("{}", o.tolerance), "--threads", std::to_string(o.common.threads),
                                   "--out", o.common.out.string()};
  for (const auto& k : o.knobs) args.insert(args.end(), {"--knob", k});
  return args;
}

int trade(TradeOptions o) {
  // Every input checked before any work: the knobs, and each setting's config (a refused one is
  // the knob's edge, reported; a refused reference stops here).
  campaigns::TradeRequest request;
  request.config = railway::load_push_config(o.config);
  request.model = campaigns::parse_model(o.model, "--model");
  request.seeds = campaigns::parse_seeds(o.seeds, "--seeds");
  request.tolerance = o.tolerance / 100.0;
  for (const auto& k : o.knobs) {
    auto knob = campaigns::parse_knob(k, "--knob");
    for (const auto& earlier : request.knobs)
      if (earlier.spec == knob.spec) throw config::ConfigError(fmt::format("--knob {}: the knob is given twice", k));
    request.knobs.push_back(std::move(knob));
  }
  const campaigns::TradePlan plan = campaigns::plan_trade(request);
  const CampaignShare share = campaign_share(o.slice, o.jobs);
  if (!share.writes_tables() || o.worker) o.common.quiet = true;

  runs::RunStore store(o.common.out);
  if (const int cleared = store.clear_abandoned(); cleared > 0 && !o.common.quiet)
    fmt::print(std::cerr, "cleared {} runs in progress left by stopped processes\n", cleared);
  campaigns::RunContext context;
  context.revision = git_revision();
  const std::size_t total = plan.compare.models.size() * request.seeds.size();
  if (!o.common.quiet) {
    fmt::print(std::cerr, "trade: {} on {}, {} settings x {} seeds = {} runs; runs in {}\n", request.model.text(request.config),
               request.config.name, plan.compare.models.size(), request.seeds.size(), total, o.common.out.string());
    for (const auto& s : plan.settings)
      if (!s.refused.empty()) fmt::print(std::cerr, "  {} is refused before it runs: {}\n", s.label, s.refused);
  }
  const auto keys = campaigns::run_keys(plan.compare);
  const auto in_store = [&] { return store.count_published(keys); };
  scene::Progress progress("trade", double(total), o.common.quiet);
  {
    PeriodicReport report([&] {
      const std::size_t done = in_store();
      progress.update(double(done), campaign_progress_detail(store, fmt::format("{} of {} runs in the store", done, total)));
    }, !o.common.quiet);
    const auto now = [&] { report.now(); };
    run_with_jobs(o.jobs, worker_args(o), o.common.out, share.slice,
                  [&](const campaigns::RunSlice& slice) { campaigns::run_compare(store, plan.compare, context, now, 0, slice); },
                  now);
  }
  progress.finish();
  if (share.mpi) wait_for_all_ranks();
  if (!share.writes_tables() || o.worker) return 0;
  const auto missing = keys.size() - in_store();
  if (other_slices_pending(share, static_cast<std::size_t>(missing), "trade")) return 0;
  store.write_index();
  const campaigns::TradeTable table = campaigns::trade_table(store, request, plan);
  const fs::path markdown = o.common.out / "trade.md", csv = o.common.out / "trade.csv";
  write_report(markdown, true, [&](std::ostream& out) { campaigns::write_trade_markdown(out, table); });
  campaigns::write_trade_csv(csv, table);
  if (!o.common.quiet) {
    campaigns::print_trade_table(std::cout, table);
    fmt::print("  written: {}, {}, {}\n", markdown.string(), csv.string(), (o.common.out / "index.csv").string());
  }
  if (o.figures) {
    std::vector<std::string> args = {o.common.out.string()};
    if (!o.compare_study.empty()) args.insert(args.end(), {"--compare", o.compare_study.string()});
    if (o.common.quiet) args.emplace_back("--quiet");
    draw_figures("trade_figures", args);
  }
  return 0;
}

}  // namespace

void add_trade_command(CLI::App& app, Action& action) {
  auto o = std::make_shared<TradeOptions>();
  o->common.out = "out/trade";
  o->common.threads = 0;
  CLI::App* command =
      app.add_subcommand("trade", "What the numerical knobs buy (speed against error) and where each stops being safe");
  command->add_option("config", o->config, "A preset (mini, study, standard, paper) or a study config file")->required();
  command->add_option("--knob", o->knobs,
                      "A knob and its values, NAME=V1,V2,...: time_step_safety, velocity (m/s), push_damping, "
                      "stiffness_scaling, creep_ratio; give --knob once per knob")
      ->required();
  command->add_option("--model", o->model, "The model every setting runs")->capture_default_str();
  command->add_option("--seeds", o->seeds, "Seeds: 1-3, 1,3,7 or 2-4,9")->capture_default_str();
  command->add_option("--tolerance", o->tolerance, "The verdict's tolerance on both outputs, %")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  add_slice_option(*command, o->slice);
  add_jobs_options(*command, o->jobs, o->worker);
  command->add_option("--compare-study", o->compare_study,
                      "The folder of an `mfdem compare` study of the same config: its models drawn on the same axes")
      ->check(CLI::ExistingDirectory);
  command->add_flag("!--no-figures", o->figures, "Write the tables only (no PNG/SVG)");
  add_common_options(*command, o->common);
  command->footer(
      "The reference setting is every knob at its accurate end (the smallest step, the slowest push, no\n"
      "damping, full stiffness); each other setting changes one knob. Runs are paired by seed and kept in the\n"
      "run store (OUT/runs/KEY), so the same command again recomputes nothing. A setting the config refuses,\n"
      "or a run a guard stops, marks the knob's stability edge. Writes OUT/trade.md, OUT/trade.csv and\n"
      "OUT/figures/trade.png/.svg (docs/trade.md).");
  command->callback([o, &action] {
    action = [o] {
      refuse_single_seed(o->common, "trade");
      apply_thread_count(o->common);
      return trade(*o);
    };
  });
}

}  // namespace mfdem::cli
