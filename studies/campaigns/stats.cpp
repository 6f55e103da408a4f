#include "studies/campaigns/stats.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>
#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>

#include "dem/hdf5_io.hpp"
#include "studies/campaigns/compare.hpp"
#include "studies/campaigns/compare_figures.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/push_output.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::campaigns {
namespace {

namespace fs = std::filesystem;
namespace h5 = dem::h5;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool contains(const std::vector<std::uint64_t>& seeds, std::uint64_t seed) {
  return std::find(seeds.begin(), seeds.end(), seed) != seeds.end();
}

std::optional<runs::RunRecord> finished_run(const runs::RunStore& store, const StatsRequest& request,
                                             const Model& model, std::uint64_t seed) {
  auto record = store.find(run_key(request.config, model, seed));
  if (record && !record->finished()) return std::nullopt;
  return record;
}

bool width_met(const MeanInterval& m, double width) {
  return m.n >= 2 && m.mean != 0.0 && m.half_width <= width * std::abs(m.mean);
}

std::string seed_list(const std::vector<std::uint64_t>& seeds) {
  // Runs of consecutive seeds as ranges: 1-10,12.
  std::string out;
  for (std::size_t k = 0; k < seeds.size();) {
    std::size_t j = k;
    while (j + 1 < seeds.size() && seeds[j + 1] == seeds[j] + 1) ++j;
    if (!out.empty()) out += ",";
    out += j > k + 1 ? fmt::format("{}-{}", seeds[k], seeds[j])
                     : j == k + 1 ? fmt::format("{},{}", seeds[k], seeds[j]) : fmt::format("{}", seeds[k]);
    k = j + 1;
  }
  return out;
}

std::string percent(double fraction) { return std::isfinite(fraction) ? fmt::format("{:.1f}", 100.0 * fraction) : "-"; }

// The words for a control variate's result on one output.
std::string control_verdict(const OutputStatistics& o) {
  if (!o.control) return o.control_note;
  const ControlVariateEstimate& e = *o.control;
  if (e.pays())
    return fmt::format("pays: at m/n = {:.1f} its variance is {:.2f} of the model's runs alone at equal cost",
                       e.optimal_ratio, e.variance_ratio_optimal);
  return fmt::format("does not pay: rho = {:.2f} is too weak for a cost ratio of {:.2f} (variance {:.2f} x plain "
                     "sampling at best)", e.correlation, e.cost_ratio, e.variance_ratio_optimal);
}

// The cells of an output's row after its label: N, mean, sd, cv %, t interval, bootstrap
// interval, +- %, the seeds the report width needs.
std::array<std::string, 8> summary_cells(const OutputSummary& s, double scale) {
  const bool spread = s.mean.n >= 2;
  const auto range = [&](double lo, double hi) { return fmt::format("{:.4g} - {:.4g}", lo * scale, hi * scale); };
  return {fmt::format("{}", s.mean.n),
          fmt::format("{:.4g}", s.mean.mean * scale),
          fmt::format("{:.3g}", s.mean.standard_deviation * scale),
          percent(s.variation()),
          spread ? range(s.mean.low(), s.mean.high()) : "-",
          s.bootstrap ? range(s.bootstrap->low, s.bootstrap->high) : "-",
          spread ? percent(s.relative_half_width()) : "-",
          s.seeds_for_width ? fmt::format("{}", *s.seeds_for_width) : "-"};
}

// The cells of an output's control-variate row after its label: rho, alpha, the model alone and
// the estimate with their 95 % half-widths, the variance as run, m/n*, the variance at m/n*.
std::array<std::string, 7> control_cells(const ControlVariateEstimate& e, double scale) {
  return {fmt::format("{:.3f}", e.correlation),
          fmt::format("{:.3f}", e.alpha),
          fmt::format("{:.4g} +- {:.3g}", e.plain_mean * scale, e.plain_half_width * scale),
          fmt::format("{:.4g} +- {:.3g}", e.estimate * scale, e.half_width * scale),
          fmt::format("{:.2f}", e.variance_ratio_as_run),
          fmt::format("{:.1f}", e.optimal_ratio),
          fmt::format("{:.2f}", e.variance_ratio_optimal)};
}

ForceUnit table_unit(const StatsTable& t) {
  double largest = 0.0;
  for (const auto& o : t.outputs) largest = std::max(largest, std::abs(o.summary.mean.mean));
  return force_unit(largest);
}

std::string width_line(const StatsTable& t) {
  if (!(t.until_width > 0.0)) return "";
  const OutputStatistics* o = nullptr;
  for (const auto& out : t.outputs)
    if (t.width_output == out.name.number) o = &out;
  if (o == nullptr) return "";
  const double reached = o->summary.relative_half_width();
  if (t.width_met)
    return fmt::format("--until-width {:g} % on the {}: met after {} seeds (+-{:.2f} %)", 100.0 * t.until_width,
                       o->name.label, o->summary.mean.n, 100.0 * reached);
  std::string more = o->summary.seeds_for_width
                         ? fmt::format("; about {} seeds would meet it at the scatter measured", *o->summary.seeds_for_width)
                         : "";
  return fmt::format("--until-width {:g} % on the {}: NOT met, the budget of {} seeds is spent (+-{:.2f} % after {} "
                     "finished){}", 100.0 * t.until_width, o->name.label, t.max_seeds, 100.0 * reached,
                     o->summary.mean.n, more);
}

}  // namespace

const std::vector<OutputName>& stats_outputs() {
  static const std::vector<OutputName> outputs = {
      {number::kPeakForce, "peak lateral force"},
      {number::kMaxContactForce, "maximum contact force"},
      {number::kContactForceQ999, "99.9 % quantile of the contact force"},
      {number::kMeanForce, "mean lateral force"}};
  return outputs;
}

void check_stats_request(const StatsRequest& r) {
  if (r.seeds.empty()) throw config::ConfigError("--seeds: no seed given");
  if (r.until_width < 0.0 || r.until_width >= 1.0)
    throw config::ConfigError(fmt::format("--until-width {:g} %: expected a width above 0 and below 100 %", 100.0 * r.until_width));
  if (r.until_width > 0.0 && !r.slice.whole())
    throw config::ConfigError(fmt::format("--until-width with a share of {} processes (--slice or mpirun): the seeds "
                                          "it adds are chosen one after another; run the search as one process",
                                          r.slice.count));
  if (r.until_width > 0.0 && r.max_seeds < r.seeds.size())
    throw config::ConfigError(fmt::format("--max-seeds {}: fewer than the {} seeds of --seeds; the budget of "
                                          "--until-width counts every seed run", r.max_seeds, r.seeds.size()));
  if (std::none_of(stats_outputs().begin(), stats_outputs().end(),
                   [&](const OutputName& o) { return r.width_output == o.number; }))
    throw config::ConfigError(fmt::format("--width-output {}: expected one of peak_force, max_contact_force, "
                                          "contact_force_q999, mean_force", r.width_output));
  if (!r.control) {
    if (!r.control_seeds.empty())
      throw config::ConfigError("--control-seeds: given without --control (the cheap model they are for)");
    return;
  }
  if (r.control->text(r.config) == r.model.text(r.config))
    throw config::ConfigError(fmt::format("--control {}: the model itself; a control variate is a cheaper model",
                                          r.control->text(r.config)));
  if (r.until_width > 0.0)
    throw config::ConfigError("--until-width with --control: the control variate's seeds are fixed by "
                              "--control-seeds; search the width without --control first");
  if (r.seeds.size() < 3)
    throw config::ConfigError(fmt::format("--seeds {}: the control variate needs at least 3 seeds of the model "
                                          "(paired with the cheap model) to estimate its correlation",
                                          seed_list(r.seeds)));
  std::vector<std::uint64_t> missing;
  for (std::uint64_t s : r.seeds)
    if (!contains(r.control_seeds, s)) missing.push_back(s);
  if (!missing.empty())
    throw config::ConfigError(fmt::format("--control-seeds {}: lacks seeds {} of --seeds; the cheap model runs on "
                                          "every seed of the model (paired) and on more",
                                          seed_list(r.control_seeds), seed_list(missing)));
}

std::vector<std::uint64_t> stats_seeds(const runs::RunStore& store, const StatsRequest& request) {
  std::vector<std::uint64_t> seeds = request.seeds;
  if (!(request.until_width > 0.0)) return seeds;
  // The width output over the runs so far: each record read once, as the seeds are walked.
  std::vector<double> values;
  for (std::size_t read = 0;;) {
    for (; read < seeds.size(); ++read) {
      const std::string key = run_key(request.config, request.model, seeds[read]);
      if (!store.has(key)) return seeds;  // not decidable yet
      if (const auto r = store.find(key); r && r->finished())
        if (const auto v = r->number(request.width_output)) values.push_back(*v);
    }
    if (width_met(mean_interval(values), request.until_width)) return seeds;
    if (seeds.size() >= request.max_seeds) return seeds;
    seeds.push_back(*std::max_element(seeds.begin(), seeds.end()) + 1);
  }
}

std::vector<std::uint64_t> run_stats(const runs::RunStore& store, const StatsRequest& request, const RunMaker& make,
                                     const std::function<void(std::size_t, std::size_t)>& after_run) {
  std::size_t done = 0;
  const auto planned = [&](const std::vector<std::uint64_t>& seeds) { return seeds.size() + request.control_seeds.size(); };
  if (!(request.until_width > 0.0)) {
    // The runs in order, model then control: a slice takes its places in that list.
    const std::size_t n = request.seeds.size();
    for (std::size_t k = 0; k < n + request.control_seeds.size(); ++k) {
      if (!request.slice.holds(k)) continue;
      if (k < n) make(request.model, request.seeds[k]);
      else make(*request.control, request.control_seeds[k - n]);
      if (after_run) after_run(++done, planned(request.seeds));
    }
    return request.seeds;
  }
  // Until the width: the next seed is decided by the runs so far.
  std::set<std::uint64_t> attempted;
  for (;;) {
    const std::vector<std::uint64_t> seeds = stats_seeds(store, request);
    const auto next = std::find_if(seeds.begin(), seeds.end(), [&](std::uint64_t s) {
      return !store.has(run_key(request.config, request.model, s)) && !attempted.count(s);
    });
    if (next == seeds.end()) return seeds;
    attempted.insert(*next);  // a run another process holds is not waited for
    make(request.model, *next);
    if (after_run) after_run(++done, planned(seeds));
  }
}

StatsTable stats_table(const runs::RunStore& store, const StatsRequest& request, const std::vector<std::uint64_t>& seeds) {
  StatsTable t;
  t.config = request.config.name;
  t.model = request.model.text(request.config);
  t.seeds = seeds;
  t.report_width = request.until_width > 0.0 ? request.until_width : request.report_width;
  t.until_width = request.until_width;
  t.width_output = request.width_output;
  t.max_seeds = request.max_seeds;
  std::set<std::string> revisions;
  std::vector<runs::RunRecord> runs;  // finished, in run order
  std::vector<double> deposition, preparation, push;
  for (std::uint64_t seed : seeds) {
    const auto record = store.find(run_key(request.config, request.model, seed));
    if (!record) continue;
    revisions.insert(record->revision);
    if (!record->finished()) {
      t.failures.push_back(fmt::format("seed {}: {}", seed, record->message));
      continue;
    }
    runs.push_back(*record);
    deposition.push_back(record->number(number::kDepositionWall).value_or(0.0));
    preparation.push_back(record->number(number::kPreparationWall).value_or(0.0));
    push.push_back(record->number(number::kPushWall).value_or(0.0));
  }
  t.finished = runs.size();
  t.deposition_wall = mean_of(deposition);
  t.preparation_wall = mean_of(preparation);
  t.push_wall = mean_of(push);

  // The control model's finished runs, by seed.
  std::vector<std::pair<std::uint64_t, runs::RunRecord>> cheap;
  if (request.control) {
    t.control_model = request.control->text(request.config);
    std::vector<double> walls, cheap_deposition;
    for (std::uint64_t seed : request.control_seeds)
      if (const auto record = store.find(run_key(request.config, *request.control, seed))) {
        revisions.insert(record->revision);
        if (!record->finished()) {
          t.failures.push_back(fmt::format("{} seed {}: {}", t.control_model, seed, record->message));
          continue;
        }
        cheap.emplace_back(seed, *record);
        walls.push_back(record->number(number::kPreparationWall).value_or(0.0) +
                        record->number(number::kPushWall).value_or(0.0));
        cheap_deposition.push_back(record->number(number::kDepositionWall).value_or(0.0));
      }
    t.control_finished = cheap.size();
    t.control_wall = mean_of(walls);
    const double seed_cost = mean_of(cheap_deposition);
    t.reference_cost = t.preparation_wall + t.push_wall;
    t.cheap_cost = seed_cost + t.control_wall;
    t.plain_cost = seed_cost + t.reference_cost;
  }
  t.revisions.assign(revisions.begin(), revisions.end());

  const double width = t.report_width;
  for (const OutputName& name : stats_outputs()) {
    OutputStatistics o;
    o.name = name;
    for (const auto& r : runs)
      if (const auto v = r.number(name.number); v && std::isfinite(*v)) {
        o.values.push_back(*v);
        o.seeds.push_back(static_cast<std::uint64_t>(*r.number(number::kSeed)));
      }
    o.summary = summarise_output(o.values, request.bootstrap, width);
    if (request.control) {
      std::vector<double>& reference = o.model_paired;
      for (const auto& [seed, record] : cheap) {
        const auto v = record.number(name.number);
        if (!v || !std::isfinite(*v)) continue;
        const auto at = std::find(o.seeds.begin(), o.seeds.end(), seed);
        if (at != o.seeds.end()) {
          o.cheap_paired.push_back(*v);
          reference.push_back(o.values[static_cast<std::size_t>(at - o.seeds.begin())]);
        } else if (!contains(seeds, seed)) {
          o.cheap_extra.push_back(*v);
        }
      }
      if (reference.size() < 3) o.control_note = fmt::format("no estimate: {} paired seeds (3 needed)", reference.size());
      else if (!(t.reference_cost > 0.0) || !(t.cheap_cost > 0.0)) o.control_note = "no estimate: the runs' costs are not recorded";
      else {
        try {
          o.control = control_variate_estimate(reference, o.cheap_paired, o.cheap_extra, t.reference_cost, t.cheap_cost,
                                               t.plain_cost);
        } catch (const std::invalid_argument&) {
          o.control_note = "no estimate: the cheap model's output does not vary between seeds";
        }
      }
    }
    t.outputs.push_back(std::move(o));
  }
  for (const auto& o : t.outputs)
    if (o.name.number == request.width_output) t.width_met = width_met(o.summary.mean, request.until_width);
  return t;
}

void print_stats_table(std::ostream& out, const StatsTable& t) {
  const auto [scale, unit] = table_unit(t);
  fmt::print(out, "\nStats: {} of {} on {} seeds ({}){}\n", t.model, t.config, t.finished, seed_list(t.seeds),
             t.failures.empty() ? "" : fmt::format(", {} failed", t.failures.size()));
  fmt::print(out, "  per seed: deposition {}, preparation {}, push {} (means)\n", scene::format_duration(t.deposition_wall),
             scene::format_duration(t.preparation_wall), scene::format_duration(t.push_wall));
  const std::string row = "  {:<38} {:>3} {:>9} {:>8} {:>6} {:>21} {:>21} {:>7} {:>14}\n";
  fmt::print(out, "\n");
  fmt::print(out, fmt::runtime(row), fmt::format("output, in {}", unit), "N", "mean", "sd", "cv %", "95 % t interval",
             "95 % bootstrap", "+- %", fmt::format("seeds +-{:g} %", 100.0 * t.report_width));
  for (const auto& o : t.outputs) {
    const auto c = summary_cells(o.summary, scale);
    fmt::print(out, fmt::runtime(row), o.name.label, c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]);
  }
  fmt::print(out, "  (cv: standard deviation over the mean, the scatter between packings; +- %: the 95 % Student-t "
                  "half-width over the mean;\n   seeds +-{:g} %: the seeds that half-width needs at the scatter measured)\n",
             100.0 * t.report_width);
  if (const std::string line = width_line(t); !line.empty()) fmt::print(out, "\n{}\n", line);
  if (!t.control_model.empty()) {
    std::size_t extra = 0;
    for (const auto& o : t.outputs) extra = std::max(extra, o.cheap_extra.size());
    fmt::print(out, "\nControl variate: {} on {} seeds ({} paired with the model, {} more)\n", t.control_model,
               t.control_finished, t.control_finished - extra, extra);
    fmt::print(out, "  cost per run: the model {}, the cheap model with its seed's deposition {}; ratio {:.2f}\n",
               scene::format_duration(t.reference_cost), scene::format_duration(t.cheap_cost),
               t.cheap_cost > 0.0 ? t.reference_cost / t.cheap_cost : 0.0);
    const std::string control_row = "  {:<38} {:>6} {:>7} {:>22} {:>22} {:>9} {:>7} {:>9}\n";
    fmt::print(out, fmt::runtime(control_row), "output", "rho", "alpha", "model alone", "control variate", "as run",
               "m/n*", "at m/n*");
    for (const auto& o : t.outputs) {
      if (!o.control) {
        fmt::print(out, "  {:<38} {}\n", o.name.label, o.control_note);
        continue;
      }
      const auto c = control_cells(*o.control, scale);
      fmt::print(out, fmt::runtime(control_row), o.name.label, c[0], c[1], c[2], c[3], c[4], c[5], c[6]);
    }
    fmt::print(out, "  (as run / at m/n*: the estimator's variance against the model's runs alone of the same cost; "
                    "below 1 the cheap runs pay)\n");
    for (const auto& o : t.outputs) fmt::print(out, "  {:<38} {}\n", o.name.label, control_verdict(o));
  }
  for (const auto& f : t.failures) fmt::print(out, "  failed: {}\n", f);
  if (t.revisions.size() > 1)
    fmt::print(out, "  note: the runs were computed by {} code revisions ({})\n", t.revisions.size(), fmt::join(t.revisions, ", "));
}

void write_stats_markdown(std::ostream& out, const StatsTable& t) {
  const auto [scale, unit] = table_unit(t);
  fmt::print(out, "# Stats: {} of {} on {} seeds\n\n", t.model, t.config, t.finished);
  fmt::print(out, "Seeds {} ({} finished{}); per seed: deposition {}, preparation {}, push {} (means).\n\n",
             seed_list(t.seeds), t.finished, t.failures.empty() ? "" : fmt::format(", {} failed", t.failures.size()),
             scene::format_duration(t.deposition_wall), scene::format_duration(t.preparation_wall),
             scene::format_duration(t.push_wall));
  fmt::print(out, "| output | N | mean ({0}) | sd ({0}) | cv % | 95 % t interval ({0}) | 95 % bootstrap ({0}) | +- % | seeds for +-{1:g} % |\n",
             unit, 100.0 * t.report_width);
  fmt::print(out, "|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& o : t.outputs)
    fmt::print(out, "| {} | {} |\n", o.name.label, fmt::join(summary_cells(o.summary, scale), " | "));
  fmt::print(out, "\ncv: the standard deviation over the mean (the scatter between packings). +- %: the half-width of "
                  "the 95 % Student-t interval over the mean. Bootstrap: the percentile interval of {} resamples "
                  "(no normality assumed). Seeds for +-{:g} %: the seeds that half-width needs at the scatter "
                  "measured.\n", BootstrapSettings{}.resamples, 100.0 * t.report_width);
  if (const std::string line = width_line(t); !line.empty()) fmt::print(out, "\n{}\n", line);
  if (!t.control_model.empty()) {
    fmt::print(out, "\n## Control variate: {}\n\n", t.control_model);
    fmt::print(out, "Cost per run: the model {}, the cheap model with its seed's deposition {} (ratio {:.2f}); {} cheap "
                    "runs.\n\n", scene::format_duration(t.reference_cost), scene::format_duration(t.cheap_cost),
               t.cheap_cost > 0.0 ? t.reference_cost / t.cheap_cost : 0.0, t.control_finished);
    fmt::print(out, "| output | rho | alpha | model alone ({0}) | control variate ({0}) | variance as run | m/n* | variance at m/n* | verdict |\n", unit);
    fmt::print(out, "|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& o : t.outputs) {
      if (!o.control)
        fmt::print(out, "| {} | - | - | - | - | - | - | - | {} |\n", o.name.label, o.control_note);
      else
        fmt::print(out, "| {} | {} | {} |\n", o.name.label, fmt::join(control_cells(*o.control, scale), " | "),
                   control_verdict(o));
    }
    fmt::print(out, "\nThe estimator (Peherstorfer, Willcox & Gunzburger 2016): mean of the model's n runs + alpha x "
                    "(mean of the cheap model's m runs - its mean on the model's n seeds); +- is the 95 % interval. "
                    "Variance: against the model's runs alone at the same cost (below 1 the cheap runs pay), as run "
                    "(m/n as made) and at the best split m/n*.\n");
  }
  for (const auto& f : t.failures) fmt::print(out, "\nFailed: {}\n", f);
  if (t.revisions.size() > 1)
    fmt::print(out, "\nThe runs were computed by {} code revisions ({}).\n", t.revisions.size(), fmt::join(t.revisions, ", "));
}

void write_stats_csv(const fs::path& file, const StatsTable& t) {
  std::ofstream out(file);
  out << "output,n,mean,standard_deviation,variation,t_low,t_high,relative_half_width,bootstrap_low,bootstrap_high,"
         "report_width,seeds_for_width,control_model,correlation,alpha,control_estimate,control_half_width,"
         "variance_ratio_as_run,optimal_ratio,variance_ratio_optimal\n";
  const auto number = [](double v) { return std::isfinite(v) ? fmt::format("{:.10g}", v) : std::string(); };
  for (const auto& o : t.outputs) {
    const OutputSummary& s = o.summary;
    const bool spread = s.mean.n >= 2;
    fmt::print(out, "{},{},{},{},{},{},{},{},{},{},{},{},{}", o.name.number, s.mean.n, number(s.mean.mean),
               number(s.mean.standard_deviation), number(s.variation()), spread ? number(s.mean.low()) : "",
               spread ? number(s.mean.high()) : "", spread ? number(s.relative_half_width()) : "",
               s.bootstrap ? number(s.bootstrap->low) : "", s.bootstrap ? number(s.bootstrap->high) : "",
               number(t.report_width), s.seeds_for_width ? fmt::format("{}", *s.seeds_for_width) : "", t.control_model);
    if (o.control)
      fmt::print(out, ",{},{},{},{},{},{},{}\n", number(o.control->correlation), number(o.control->alpha),
                 number(o.control->estimate), number(o.control->half_width), number(o.control->variance_ratio_as_run),
                 number(o.control->optimal_ratio), number(o.control->variance_ratio_optimal));
    else
      out << ",,,,,,,\n";
  }
}

void write_stats_figure_data(const fs::path& path, const runs::RunStore& store, const StatsRequest& request,
                             const StatsTable& table) {
  std::vector<railway::ForceCurve> curves;
  for (std::uint64_t seed : table.seeds)
    if (const auto r = finished_run(store, request, request.model, seed); r && fs::exists(store.run_folder(r->key) / "push.h5"))
      curves.push_back(railway::read_force_curve(store.run_folder(r->key) / "push.h5"));
  const CurveBand band = curve_band(table.model, curves);
  const auto finite_or_nan = [](double v) { return std::isfinite(v) ? v : kNaN; };
  h5::write_file(path, [&](hid_t file) {
    h5::write_attribute(file, "config", table.config);
    h5::write_attribute(file, "model", table.model);
    h5::write_attribute(file, "seeds", double(table.finished));
    h5::write_attribute(file, "control_model", table.control_model);
    h5::write_attribute(file, "until_width", table.until_width);
    h5::write_attribute(file, "report_width", table.report_width);
    h5::write_attribute(file, "width_output", table.width_output);
    for (std::size_t k = 0; k < table.outputs.size(); ++k) {
      const OutputStatistics& o = table.outputs[k];
      const OutputSummary& s = o.summary;
      const hid_t g = h5::make_group(file, fmt::format("outputs/{:02d}", k));
      h5::write_attribute(g, "number", std::string(o.name.number));
      h5::write_attribute(g, "label", std::string(o.name.label));
      h5::write_attribute(g, "mean", s.mean.mean);
      h5::write_attribute(g, "half_width", finite_or_nan(s.mean.half_width));
      h5::write_attribute(g, "standard_deviation", s.mean.standard_deviation);
      h5::write_attribute(g, "bootstrap_low", s.bootstrap ? s.bootstrap->low : kNaN);
      h5::write_attribute(g, "bootstrap_high", s.bootstrap ? s.bootstrap->high : kNaN);
      std::vector<double> seeds(o.seeds.begin(), o.seeds.end()), running_mean, running_half;
      for (const auto& r : s.running) {
        running_mean.push_back(r.mean);
        running_half.push_back(finite_or_nan(r.half_width));
      }
      h5::write_doubles(g, "seeds", seeds);
      h5::write_doubles(g, "values", o.values);
      h5::write_doubles(g, "running_mean", running_mean);
      h5::write_doubles(g, "running_half_width", running_half);
      if (o.control) {
        const ControlVariateEstimate& e = *o.control;
        h5::write_doubles(g, "model_paired", o.model_paired);
        h5::write_doubles(g, "cheap_paired", o.cheap_paired);
        h5::write_doubles(g, "cheap_extra", o.cheap_extra);
        for (const auto& [name, value] : {std::pair{"estimate", e.estimate}, {"estimate_half_width", e.half_width},
                                          {"alpha", e.alpha}, {"correlation", e.correlation},
                                          {"variance_ratio_optimal", e.variance_ratio_optimal},
                                          {"variance_ratio_as_run", e.variance_ratio_as_run},
                                          {"optimal_ratio", finite_or_nan(e.optimal_ratio)}})
          h5::write_attribute(g, name, value);
      }
      H5Gclose(g);
    }
    const hid_t c = h5::make_group(file, "curve");
    h5::write_doubles(c, "u", band.u);
    h5::write_doubles(c, "mean", band.mean);
    h5::write_doubles(c, "low", band.low);
    h5::write_doubles(c, "high", band.high);
    H5Gclose(c);
  });
}

}  // namespace mfdem::campaigns
