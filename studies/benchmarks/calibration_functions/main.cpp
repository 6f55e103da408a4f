// The surrogate calibration loop against NLopt applied directly, on analytic functions with known
// optima (README.md beside this file). Not a test: a benchmark of evaluations, run by hand.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>

#include "calibration/calibration_loop.hpp"
#include "calibration/posterior.hpp"
#include "studies/benchmarks/calibration_functions/direct_search.hpp"

using namespace mfdem;
using benchmarks::TestFunction;
using benchmarks::TracePoint;

namespace {

constexpr double kTolerance = 0.01;        // of the function's range: the criterion
constexpr double kStrictTolerance = 0.001;  // a tenth of it, where a lucky early point counts for less

struct Outcome {
  std::vector<TracePoint> trace;
  int covered = -1;  // surrogate on a noisy variant: whether the 90 % intervals hold a minimiser
};

// The first cost at which the returned point is within tolerance; infinity if never.
double cost_to_reach(const std::vector<TracePoint>& trace, double tolerance) {
  for (const auto& p : trace)
    if (p.gap <= tolerance) return p.cost;
  return std::numeric_limits<double>::infinity();
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double at = q * double(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(at)), hi = static_cast<std::size_t>(std::ceil(at));
  if (std::isinf(v[hi])) return v[hi];
  return v[lo] + (at - double(lo)) * (v[hi] - v[lo]);
}

Outcome surrogate_run(const TestFunction& t, const std::function<double(const Eigen::VectorXd&)>& observe_cheap,
                      const std::function<double(const Eigen::VectorXd&)>& observe, double noise, int budget,
                      std::uint64_t seed) {
  calibration::LoopOptions o;
  o.bounds = t.bounds;
  o.targets = {calibration::relative_target(t.minimum)};
  o.two_levels = static_cast<bool>(t.cheap);
  o.cheap_cost = 0.25;
  o.budget = budget;
  o.stop_improvement = 0.0;
  o.design_seed = seed;
  Outcome out;
  const double strict = kStrictTolerance * t.range;
  // Stopped once the strict tolerance is reached: what comes later is not counted.
  o.on_step = [&](const calibration::LoopStep& step) {
    out.trace.push_back({step.cost, t.f(step.returned) - t.minimum});
    return out.trace.back().gap > strict;
  };
  const auto result = calibration::run_calibration_loop(
      calibration::one_at_a_time([&](const Eigen::VectorXd& x, std::uint64_t, calibration::Level level) {
        return Eigen::VectorXd::Constant(1, level == calibration::Level::cheap ? observe_cheap(x) : observe(x));
      }),
      o);
  if (noise > 0.0) {
    calibration::MisfitSurrogate s(o.bounds, o.targets);
    s.fit(result.runs);
    calibration::PosteriorOptions p;
    p.target_sd = {0.0};  // the target is the exact minimum; the surrogate's uncertainty is the spread
    p.seed = seed;
    const auto posterior = calibration::calibration_posterior(s, p);
    out.covered = 0;
    for (const auto& m : t.minimisers) {
      bool inside = true;
      for (Eigen::Index a = 0; a < m.size(); ++a)
        inside = inside && m(a) >= posterior.intervals[a].lower && m(a) <= posterior.intervals[a].upper;
      if (inside) out.covered = 1;
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("The surrogate calibration loop against NLopt applied directly, on analytic functions");
  int seeds = 20, direct_budget = 300, surrogate_budget = 40;
  std::vector<std::string> functions = {"branin", "hartmann3", "forrester"};
  std::vector<double> noises = {0.0, 0.01, 0.05};
  std::vector<std::string> methods = {"surrogate"};
  for (const auto& m : benchmarks::direct_methods()) methods.push_back(m);
  std::string out = "out/calibration_functions";
  app.add_option("--seeds", seeds, "Seeds per case")->capture_default_str();
  app.add_option("--functions", functions, "branin, hartmann3, forrester")->capture_default_str();
  app.add_option("--noise", noises, "Noise standard deviations, as fractions of the range")->capture_default_str();
  app.add_option("--methods", methods, "surrogate and NLopt's BOBYQA, Sbplx, DIRECT-L, ISRES, CRS2")->capture_default_str();
  app.add_option("--direct-budget", direct_budget, "Evaluations of a direct method")->capture_default_str();
  app.add_option("--surrogate-budget", surrogate_budget, "Cost of the surrogate loop, in expensive runs")->capture_default_str();
  app.add_option("--out", out, "Folder for summary.csv, convergence.csv and table.md")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::filesystem::create_directories(out);

  std::ofstream summary(out + "/summary.csv"), convergence(out + "/convergence.csv"), table(out + "/table.md");
  summary << "function,noise,method,seed,cost_to_1_percent,cost_to_0.1_percent,final_gap,covered\n";
  convergence << "function,noise,method,range,cost,median_gap,lower_quartile_gap,upper_quartile_gap\n";
  table << "| function | noise | method | cost to 1 % (median) | quartiles | reached | cost to 0.1 % (median) | reached | "
           "90 % interval holds a minimiser |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& t : benchmarks::test_functions()) {
    if (std::find(functions.begin(), functions.end(), t.name) == functions.end()) continue;
    for (double noise : noises) {
      std::map<std::string, double> medians;
      for (const auto& method : methods) {
        std::vector<double> reach, strict_reach;
        std::vector<std::vector<TracePoint>> traces;
        int covered = 0, with_posterior = 0;
        const auto started = std::chrono::steady_clock::now();
        for (int seed = 1; seed <= seeds; ++seed) {
          std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
          gsl_rng_set(rng.get(), static_cast<unsigned long>(1000 + seed));
          const double sd = noise * t.range;
          const auto observe = [&](const Eigen::VectorXd& x) { return t.f(x) + (sd > 0 ? gsl_ran_gaussian(rng.get(), sd) : 0.0); };
          const auto observe_cheap = [&](const Eigen::VectorXd& x) {
            return t.cheap(x) + (sd > 0 ? gsl_ran_gaussian(rng.get(), sd) : 0.0);
          };
          Outcome o;
          if (method == "surrogate")
            o = surrogate_run(t, observe_cheap, observe, noise, surrogate_budget, static_cast<std::uint64_t>(seed));
          else
            o.trace = benchmarks::direct_search(method, t, observe, direct_budget, static_cast<std::uint64_t>(seed));
          reach.push_back(cost_to_reach(o.trace, kTolerance * t.range));
          strict_reach.push_back(cost_to_reach(o.trace, kStrictTolerance * t.range));
          if (o.covered >= 0) covered += o.covered, ++with_posterior;
          summary << fmt::format("{},{},{},{},{},{},{:.6g},{}\n", t.name, noise, method, seed, reach.back(),
                                 strict_reach.back(), o.trace.empty() ? NAN : o.trace.back().gap, o.covered);
          traces.push_back(std::move(o.trace));
        }
        // Convergence: the gap of the returned point against cost, carried forward, over seeds.
        const int budget = method == "surrogate" ? surrogate_budget : direct_budget;
        double last_cost = 0.0;  // the curve ends where the last seed stopped
        for (const auto& trace : traces)
          if (!trace.empty()) last_cost = std::max(last_cost, trace.back().cost);
        for (int c = 1; c <= budget && c <= last_cost + 1e-9; ++c) {
          std::vector<double> gaps;
          for (const auto& trace : traces) {
            double gap = std::numeric_limits<double>::infinity();
            for (const auto& p : trace)
              if (p.cost <= c + 1e-9) gap = p.gap;
            if (!trace.empty() && trace.back().cost <= c && trace.back().gap <= kStrictTolerance * t.range)
              gap = trace.back().gap;  // stopped once reached: stays reached
            gaps.push_back(gap);
          }
          convergence << fmt::format("{},{},{},{:.6g},{},{:.6g},{:.6g},{:.6g}\n", t.name, noise, method, t.range, c,
                                     quantile(gaps, 0.5),
                                     quantile(gaps, 0.25), quantile(gaps, 0.75));
        }
        const double median = quantile(reach, 0.5);
        medians[method] = median;
        const auto reached = [](const std::vector<double>& r) {
          return std::count_if(r.begin(), r.end(), [](double c) { return std::isfinite(c); });
        };
        const auto cost_text = [&](double c) { return std::isfinite(c) ? fmt::format("{:.1f}", c) : fmt::format("> {}", budget); };
        const std::string row = fmt::format(
            "| {} | {:.0f} % | {} | {} | {} - {} | {}/{} | {} | {}/{} | {} |", t.name, noise * 100, method, cost_text(median),
            cost_text(quantile(reach, 0.25)), cost_text(quantile(reach, 0.75)), reached(reach), seeds,
            cost_text(quantile(strict_reach, 0.5)), reached(strict_reach), seeds,
            with_posterior > 0 ? fmt::format("{}/{}", covered, with_posterior) : "");
        table << row << "\n";
        table.flush();
        fmt::print("{}   ({:.1f} s)\n", row,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
