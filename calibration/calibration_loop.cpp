#include "calibration/calibration_loop.hpp"

#include <fmt/format.h>

#include <optional>
#include <stdexcept>

#include "calibration/loop_record.hpp"
#include "calibration/sobol_design.hpp"

namespace mfdem::calibration {
namespace {

// What decides the runs (not the budget or the stopping threshold: raising them continues a loop).
std::string fingerprint(const LoopOptions& o) {
  std::string s = fmt::format(
      "two_levels={} cheap_cost={:.17g} initial={}/{} batch={} design_seed={} kernel={} lengths={:.6g}-{:.6g} bounds=",
      o.two_levels, o.cheap_cost, o.initial_expensive, o.initial_cheap, o.batch, o.design_seed,
      o.kind == KernelKind::matern52 ? "matern52" : "se", o.search.shortest_length, o.search.longest_length);
  for (const auto& b : o.bounds) s += fmt::format("[{:.17g} {:.17g}]", b.lower, b.upper);
  s += " targets=";
  for (const auto& t : o.targets) s += fmt::format("[{:.17g} {:.17g}]", t.value, t.scale);
  s += " seeds=";
  for (auto seed : o.run_seeds) s += fmt::format("{};", seed);
  return s;
}

Eigen::VectorXd as_vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

class Loop {
 public:
  Loop(const EvaluateBatch& evaluate, const LoopOptions& o) : evaluate_(evaluate), o_(o) {
    if (!o.record.empty())
      record_.emplace(o.record, fingerprint(o), static_cast<int>(o.bounds.size()), static_cast<int>(o.targets.size()));
  }

  double cost_of(Level level) const { return level == Level::cheap ? o_.cheap_cost : 1.0; }

  // Runs the requests, taking what the record holds; a record that disagrees with the loop's
  // own decision means the options or the code changed.
  void run(const std::vector<RunRequest>& requests) {
    std::vector<RunRequest> missing;
    for (const auto& request : requests) {
      const std::size_t k = result_.runs.size() + missing.size();
      if (missing.empty() && record_ && k < record_->runs().size()) {
        const RecordedRun& r = record_->runs()[k];
        if (r.run.level != request.level || r.seed != request.seed || r.run.parameters != request.parameters)
          throw std::runtime_error(fmt::format("{}: run {} of the record is not the run this loop asks for (the code "
                                               "changed since it was written?): give another record file",
                                               o_.record.string(), k));
        add(r.run, r.seed);
        ++result_.reused;
        continue;
      }
      missing.push_back(request);
    }
    if (missing.empty()) return;
    const auto outputs = evaluate_(missing);
    if (outputs.size() != missing.size()) throw std::runtime_error("calibration: the model returned too few results");
    for (std::size_t i = 0; i < missing.size(); ++i) {
      const Evaluation e{missing[i].parameters, missing[i].level, outputs[i]};
      if (e.outputs.size() != static_cast<Eigen::Index>(o_.targets.size()) || !e.outputs.allFinite())
        throw std::runtime_error(fmt::format("calibration: run {} returned {} outputs, not {} finite ones",
                                             result_.runs.size(), e.outputs.size(), o_.targets.size()));
      if (record_) record_->append({e, missing[i].seed});
      add(e, missing[i].seed);
    }
  }

  RunRequest request(const Eigen::VectorXd& x, Level level) const {
    const std::size_t k = result_.runs.size() + pending_;
    return {x, o_.run_seeds[k % o_.run_seeds.size()], level};
  }

  LoopResult run_all() {
    const int d = static_cast<int>(o_.bounds.size());
    const int n_expensive = o_.initial_expensive > 0 ? o_.initial_expensive : 2 * d + 2;
    const int n_cheap = o_.two_levels ? (o_.initial_cheap > 0 ? o_.initial_cheap : 3 * n_expensive) : 0;
    if (o_.two_levels && n_cheap < n_expensive)
      throw std::invalid_argument("calibration: the nested design needs at least as many cheap runs as expensive ones");
    const auto design = sobol_design(o_.bounds, std::max(n_cheap, n_expensive), o_.design_seed);
    std::vector<RunRequest> first;
    for (int k = 0; k < n_cheap; ++k) first.push_back(next_request(as_vector(design[k]), Level::cheap));
    for (int k = 0; k < n_expensive; ++k) first.push_back(next_request(as_vector(design[k]), Level::expensive));
    pending_ = 0;
    run(first);

    MisfitSurrogate surrogate(o_.bounds, o_.targets, o_.kind, o_.search);
    InfillOptions infill;
    infill.batch = o_.batch;
    infill.cheap_cost = o_.cheap_cost;
    infill.search = o_.box;
    for (;;) {
      surrogate.fit(result_.runs);
      LoopStep step;
      step.cost = result_.cost;
      step.returned = minimise_predicted_misfit(surrogate, result_.runs, o_.box.global_evaluations);
      step.predicted_misfit = surrogate.predict(step.returned).mean;
      auto proposals = propose_runs(surrogate, result_.runs, infill);
      step.expected_improvement = proposals.front().expected_improvement;
      result_.history.push_back(step);
      if (o_.on_step && !o_.on_step(step)) {
        result_.stopped_by = "caller";
        break;
      }
      if (step.expected_improvement < o_.stop_improvement) {
        result_.stopped_by = "improvement";
        break;
      }
      std::vector<RunRequest> batch;
      double cost = result_.cost;
      for (const auto& p : proposals) {
        if (cost + p.cost > o_.budget + 1e-9) break;
        cost += p.cost;
        if (p.with_cheap_twin) batch.push_back(next_request(p.parameters, Level::cheap));
        batch.push_back(next_request(p.parameters, p.level));
      }
      pending_ = 0;
      if (batch.empty()) {
        result_.stopped_by = "budget";
        break;
      }
      run(batch);
    }
    result_.history.back().expected_improvement = 0.0;
    return result_;
  }

 private:
  const EvaluateBatch& evaluate_;
  const LoopOptions& o_;
  std::optional<LoopRecord> record_;
  LoopResult result_;
  std::size_t pending_ = 0;  // requests made but not yet run, for their seeds

  RunRequest next_request(const Eigen::VectorXd& x, Level level) {
    RunRequest r = request(x, level);
    ++pending_;
    return r;
  }

  void add(const Evaluation& e, std::uint64_t seed) {
    result_.runs.push_back(e);
    result_.seeds.push_back(seed);
    result_.cost += cost_of(e.level);
  }
};

}  // namespace

EvaluateBatch one_at_a_time(Evaluate evaluate) {
  return [evaluate = std::move(evaluate)](std::span<const RunRequest> requests) {
    std::vector<Eigen::VectorXd> out;
    for (const auto& r : requests) out.push_back(evaluate(r.parameters, r.seed, r.level));
    return out;
  };
}

LoopResult run_calibration_loop(const EvaluateBatch& evaluate, const LoopOptions& options) {
  if (options.bounds.empty() || options.targets.empty())
    throw std::invalid_argument("calibration: at least one parameter and one target expected");
  if (options.run_seeds.empty()) throw std::invalid_argument("calibration: at least one run seed expected");
  if (options.batch < 1) throw std::invalid_argument("calibration: a batch of at least one run expected");
  return Loop(evaluate, options).run_all();
}

}  // namespace mfdem::calibration
