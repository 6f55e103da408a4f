#pragma once
// `mfdem compare`: models run on the same beds (one deposition per seed), and the trade of each
// against the reference: what it saved (elements, contacts, wall time) and what it cost (the
// paired differences of the outputs, with 95 % intervals over seeds).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "studies/campaigns/paired_statistics.hpp"
#include "studies/campaigns/push_runs.hpp"
#include "studies/campaigns/run_slice.hpp"

namespace mfdem::campaigns {

struct CompareRequest {
  railway::PushStudyConfig config;
  std::vector<Model> models;
  std::size_t reference = 0;            // index into models
  std::vector<std::uint64_t> seeds;
  double tolerance = 0.05;              // of the verdict, relative
  // Per model, a config of its own (a numerical setting in `mfdem trade`) and the name its row
  // shows; empty: every model runs on `config` and is named by Model::text.
  std::vector<railway::PushStudyConfig> model_configs;
  std::vector<std::string> model_labels;
  const railway::PushStudyConfig& config_of(std::size_t m) const {
    return model_configs.empty() ? config : model_configs[m];
  }
  std::string label_of(std::size_t m) const { return model_labels.empty() ? models[m].text(config_of(m)) : model_labels[m]; }
};

// Parses "1-5", "1,3,7" or "2-4,9" (whole numbers >= 0, ranges ascending); throws
// config::ConfigError naming `option` and the value, also for an empty list.
std::vector<std::uint64_t> parse_seeds(const std::string& text, const std::string& option);

// The keys of the request's runs, seed by seed, the models of a seed in their order.
std::vector<std::string> run_keys(const CompareRequest& request);

// The order in which a process of a study visits its seeds (indices into the seed list), given
// which seeds still miss a run: the seeds that miss one, starting at the one `first_seed` places
// into them, then the complete ones (nothing to do there). Processes given 0, 1, ... start on
// different unfinished seeds, so each makes its own seed's deposition instead of waiting for
// another's (a study resumed on seeds 1-5 with 1-2 done: the second process starts on seed 4).
std::vector<std::size_t> seed_order(const std::vector<bool>& seed_incomplete, std::size_t first_seed);

// Runs every (seed, model) of the request not yet in the store, seed by seed (each seed's
// deposition made once, its models then), in the order of seed_order; `after_run()` is called
// after each (a progress line counts the store, which other processes fill too). With a slice,
// only the runs of the slice (their places in run_keys) are made.
void run_compare(runs::RunStore& store, const CompareRequest& request, const RunContext& context,
                 const std::function<void()>& after_run = {}, std::size_t first_seed = 0, const RunSlice& slice = {});

// One output of one model against the reference.
struct OutputRow {
  double mean = 0.0;                    // over the model's finished seeds, in the output's unit
  MeanInterval difference;              // paired relative difference from the reference
  std::vector<double> per_seed;         // the paired differences behind it: the seeds both finished, in order
};

struct ModelRow {
  std::string model;                    // Model::text
  bool reference = false;
  std::size_t seeds = 0, failed = 0;    // finished runs, failed runs
  double clumps = 0.0, balls = 0.0, elements = 0.0, contacts_at_peak = 0.0;  // means over seeds
  double preparation_wall = 0.0, push_wall = 0.0;  // s, means
  double push_speedup = 0.0, total_speedup = 0.0;  // reference's mean wall / this model's
  // What a push step costs (means over seeds): the time step, element-steps per second of push
  // wall time, active contacts per element at the peak, and the push's wall time per element-step
  // relative to the reference's (1: a ball costs what a pebble costs).
  double time_step = 0.0, steps = 0.0, element_steps_per_second = 0.0, contacts_per_element = 0.0;
  double relative_step_cost = 0.0;
  OutputRow peak_force, max_contact_force, contact_force_q999, mean_force;
  MeanInterval curve_difference;        // normalised RMS difference of F(u), per seed
  Verdict peak_verdict = Verdict::undecided, contact_verdict = Verdict::undecided;
  std::vector<std::string> failures;    // "seed 3: message"
};

struct CompareTable {
  std::string config;                   // name
  std::vector<std::uint64_t> seeds;
  std::vector<ModelRow> rows;
  double deposition_wall = 0.0;         // s, the shared deposition, mean over seeds
  double tolerance = 0.05;
  std::vector<std::string> revisions;   // of the runs; more than one: the table mixes code versions
};

// The table of the request from the store's records (finished runs; failed ones listed).
CompareTable compare_table(const runs::RunStore& store, const CompareRequest& request);

// How the campaign tables write their numbers.
// A paired difference in %: "+3.2 +- 1.1", "+3.2" from one seed, "-" from none.
std::string percent_interval(const MeanInterval& difference);
// "2.75x", or "-" when not measured.
std::string speedup_text(double speedup);
// Forces in kN on a full-size bed, in N on a small one (a mini bed's peak is about 50 N).
struct ForceUnit {
  double scale = 1.0;  // multiplies newtons
  const char* name = "N";
};
ForceUnit force_unit(double largest_newtons);

void print_compare_table(std::ostream& out, const CompareTable& table);
void write_compare_markdown(const std::filesystem::path& file, const CompareTable& table);
// One row per model, every number of the table in SI units (N, s) and fractions.
void write_compare_csv(const std::filesystem::path& file, const CompareTable& table);

}  // namespace mfdem::campaigns
