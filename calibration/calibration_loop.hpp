#pragma once
// The calibration loop over any model seen as evaluate(parameters, seed, level) -> outputs:
// an initial design (a shifted Sobol design; in a two-level study the expensive points are the
// first of the cheap ones, so the design is nested), then rounds of: fit the surrogates
// (misfit_surrogate.hpp), propose a batch (infill.hpp), run it. It stops when the best proposal's
// expected improvement falls below `stop_improvement` or the next batch would pass the budget
// (counted in expensive runs, a cheap run costing `cheap_cost`).
//
// Every finished run is appended to the record file at once (one CSV line, numbers to 17
// significant digits, so they read back bit for bit). The loop is deterministic for given
// options, so a loop started again with the same options and record replays its decisions,
// takes the recorded outputs instead of running them again, and goes on where the record ends;
// a record written with other options is refused. A line cut short by a kill is dropped.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "calibration/infill.hpp"
#include "calibration/misfit_surrogate.hpp"

namespace mfdem::calibration {

struct RunRequest {
  Eigen::VectorXd parameters;
  std::uint64_t seed = 1;
  Level level = Level::expensive;
};

// Runs the requests (in parallel if it likes) and returns their outputs in the same order.
using EvaluateBatch = std::function<std::vector<Eigen::VectorXd>(std::span<const RunRequest>)>;
// One run at a time.
using Evaluate = std::function<Eigen::VectorXd(const Eigen::VectorXd& parameters, std::uint64_t seed, Level level)>;
EvaluateBatch one_at_a_time(Evaluate evaluate);

// The state after the initial design and after each batch.
struct LoopStep {
  double cost = 0.0;           // spent so far, in expensive runs
  Eigen::VectorXd returned;    // the minimiser of the predicted misfit: what the loop would return now
  double predicted_misfit = 0.0;
  double expected_improvement = 0.0;  // of the next proposal (0 after the last)
};

struct LoopOptions {
  std::vector<Bounds> bounds;
  std::vector<Target> targets;
  bool two_levels = false;
  double cheap_cost = 0.25;     // in expensive runs
  int initial_expensive = 0;    // 0: 2 d + 2
  int initial_cheap = 0;        // two levels; 0: 3 x initial_expensive
  double budget = 30.0;         // in expensive runs, the initial design included
  int batch = 1;
  double stop_improvement = 1e-6;  // of the misfit (a sum of squared relative errors)
  std::vector<std::uint64_t> run_seeds = {1};  // run k (in the order run) uses run_seeds[k % size]
  std::uint64_t design_seed = 1;               // the Sobol design's shift
  KernelKind kind = KernelKind::matern52;
  HyperparameterSearch search;
  BoxSearch box;
  std::filesystem::path record;  // empty: nothing recorded
  // Called after the initial design and after each batch; returning false stops the loop
  // ("caller": a benchmark that knows the answer stops once it is reached).
  std::function<bool(const LoopStep&)> on_step;
};

struct LoopResult {
  std::vector<Evaluation> runs;
  std::vector<std::uint64_t> seeds;  // of each run
  std::vector<LoopStep> history;
  double cost = 0.0;
  int reused = 0;           // runs taken from the record instead of evaluated
  std::string stopped_by;   // "improvement", "budget" or "caller"
};

LoopResult run_calibration_loop(const EvaluateBatch& evaluate, const LoopOptions& options);

}  // namespace mfdem::calibration
