#pragma once
// `mfdem stats`: repeated stochastic packings of one model. N seeds (each its own deposition, so
// its own packing) and, for every output, the mean with its 95 % Student-t and bootstrap
// intervals, the standard deviation, the running mean as seeds were added and the seeds an
// interval of a requested width needs; optionally seeds added until that width is reached, and a
// cheap model on the same seeds and more as a control variate for the model's mean
// (control_variate.hpp). Runs come from and go to the run store, shared with compare and calibrate.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "studies/campaigns/control_variate.hpp"
#include "studies/campaigns/push_runs.hpp"
#include "studies/campaigns/run_slice.hpp"
#include "studies/campaigns/sample_statistics.hpp"

namespace mfdem::campaigns {

struct StatsRequest {
  railway::PushStudyConfig config;
  Model model;
  std::vector<std::uint64_t> seeds;          // run first, in this order
  // --until-width: seeds are added (the next unused numbers after the largest given) until the
  // 95 % half-width of `width_output` is at most this fraction of its mean, or `max_seeds` seeds
  // have been run. 0: the given seeds only.
  double until_width = 0.0;
  std::string width_output = number::kPeakForce;
  std::size_t max_seeds = 0;
  double report_width = 0.02;                // the width whose seed count the table gives (until_width when set)
  std::optional<Model> control;              // a cheaper model of the same config, as a control variate
  std::vector<std::uint64_t> control_seeds;  // its seeds: every seed of `seeds`, and more
  BootstrapSettings bootstrap;
  // This process's share of the runs (MPI ranks, a job array's tasks): the places in the list of
  // the model's seeds then the control model's. Not with until_width (its seeds are chosen in turn).
  RunSlice slice;
};

// The outputs summarised, in the table's order: the run-record number, the name a reader sees.
struct OutputName {
  const char* number;
  const char* label;
};
const std::vector<OutputName>& stats_outputs();

// Checks what the request's fields allow together (numbers already parsed): throws
// config::ConfigError naming the option (`--control-seeds`, `--max-seeds`, ...) and its value.
void check_stats_request(const StatsRequest& request);

// Makes sure the run of `model` on `seed` is in the store (found, or computed and recorded).
using RunMaker = std::function<void(const Model& model, std::uint64_t seed)>;

// The model's seeds in run order: the request's, then (for until_width) the added ones. The
// control model runs on its seeds after the model's. `after_run(done, planned)` follows each run.
// With a slice, only its runs are made.
std::vector<std::uint64_t> run_stats(const runs::RunStore& store, const StatsRequest& request, const RunMaker& make,
                                     const std::function<void(std::size_t, std::size_t)>& after_run = {});

// The seeds until_width needs from the store as it stands: the request's seeds then the added
// ones while the width is not met (a restarted study walks the same seeds).
std::vector<std::uint64_t> stats_seeds(const runs::RunStore& store, const StatsRequest& request);

struct OutputStatistics {
  OutputName name;
  std::vector<std::uint64_t> seeds;          // of the finished runs, in run order
  std::vector<double> values;                // N, per seed
  OutputSummary summary;
  // The control variate: the model's and the cheap model's values on the seeds both ran (paired,
  // in the cheap model's seed order), and the cheap model's on its extra seeds.
  std::vector<double> model_paired, cheap_paired, cheap_extra;
  std::optional<ControlVariateEstimate> control;
  std::string control_note;                  // why there is no estimate ("" when there is)
};

struct StatsTable {
  std::string config, model;                 // names
  std::vector<std::uint64_t> seeds;          // run, in order (finished or failed)
  std::size_t finished = 0;
  std::vector<std::string> failures;         // "seed 3: message"
  std::vector<std::string> revisions;        // of the runs; more than one: the table mixes code versions
  double deposition_wall = 0.0, preparation_wall = 0.0, push_wall = 0.0;  // s, means over finished runs
  std::vector<OutputStatistics> outputs;     // stats_outputs() order
  double report_width = 0.02;
  double until_width = 0.0;
  std::string width_output;
  std::size_t max_seeds = 0;
  bool width_met = false;
  // The control model.
  std::string control_model;
  std::size_t control_finished = 0;
  double control_wall = 0.0;                 // s, its mean preparation + push
  // Costs per run the estimator uses (the deposition counted with the cheap run, as every seed
  // needs one): w_hi = the model's preparation + push, w_lo = deposition + the cheap run's,
  // plain sampling = deposition + the model's.
  double reference_cost = 0.0, cheap_cost = 0.0, plain_cost = 0.0;
};

StatsTable stats_table(const runs::RunStore& store, const StatsRequest& request, const std::vector<std::uint64_t>& seeds);

void print_stats_table(std::ostream& out, const StatsTable& table);
void write_stats_markdown(std::ostream& out, const StatsTable& table);
// One row per output, every number in SI units (N) and fractions.
void write_stats_csv(const std::filesystem::path& file, const StatsTable& table);

// The numbers behind `mfdem stats`'s figures (drawn by studies/python/mfdem/stats_figures.py):
//   /                  attrs config, model, seeds (finished), control_model ("" without),
//                      until_width, report_width, width_output
//   /outputs/NN        attrs number, label, mean, half_width, standard_deviation, bootstrap_low,
//                      bootstrap_high (NaN below 2 seeds); seeds, values, running_mean,
//                      running_half_width (NaN for one seed); with a control variate also
//                      model_paired, cheap_paired, cheap_extra and attrs estimate, estimate_half_width, alpha,
//                      correlation, variance_ratio_optimal, variance_ratio_as_run, optimal_ratio
//   /curve             u, mean, low, high: F(u) over the finished seeds (m, N)
void write_stats_figure_data(const std::filesystem::path& path, const runs::RunStore& store,
                             const StatsRequest& request, const StatsTable& table);

}  // namespace mfdem::campaigns
