#include "studies/campaigns/compare.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>

#include "studies/config/config_error.hpp"
#include "studies/railway/push_output.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::campaigns {
namespace {

namespace fs = std::filesystem;

const char* verdict_text(Verdict v) {
  switch (v) {
    case Verdict::within: return "within";
    case Verdict::outside: return "outside";
    default: return "undecided";
  }
}

// The one-line verdict of a model: both outputs within the tolerance, or which is not, and
// whether the differences are larger than the seed-to-seed spread.
std::string verdict_line(const ModelRow& r, double tolerance) {
  if (r.reference) return "the reference";
  if (r.seeds == 0) return "no finished run";
  const int tol = static_cast<int>(std::lround(100.0 * tolerance));
  const MeanInterval& peak_difference = r.peak_force.difference;
  const MeanInterval& contact_difference = r.max_contact_force.difference;
  if (peak_difference.n < 2 || contact_difference.n < 2) {
    // No interval: say what the one seed shows, not a verdict it cannot carry.
    const auto side = [&](double d) { return std::abs(d) <= tolerance ? "within" : "outside"; };
    return fmt::format("one seed, no interval: on it the peak force differs by {:+.1f} % ({} {} %), the contact "
                       "force by {:+.1f} % ({}); more seeds would tell whether it holds",
                       100.0 * peak_difference.mean, side(peak_difference.mean), tol,
                       100.0 * contact_difference.mean, side(contact_difference.mean));
  }
  std::string line;
  if (r.peak_verdict == Verdict::within && r.contact_verdict == Verdict::within)
    line = fmt::format("within {} % on both outputs", tol);
  else if (r.peak_verdict == Verdict::outside || r.contact_verdict == Verdict::outside)
    line = fmt::format("outside {} % on {}", tol,
                       r.peak_verdict == Verdict::outside && r.contact_verdict == Verdict::outside ? "both outputs"
                       : r.peak_verdict == Verdict::outside                                       ? "the peak force"
                                                                                                  : "the contact force");
  else {
    // How many seeds would decide it, if the spread so far held: the larger of the two outputs'.
    int needed = 0;
    bool beyond = false;  // one output needs more than any campaign would run
    for (const auto& [difference, v] : {std::pair{peak_difference, r.peak_verdict}, {contact_difference, r.contact_verdict}})
      if (v == Verdict::undecided) {
        const int n = seeds_to_decide(difference, tolerance);
        if (n == 0) beyond = true;
        needed = std::max(needed, n);
      }
    line = beyond ? fmt::format("not decided at {} %: the intervals straddle it, and a mean this near the band's "
                                "edge needs more than 1000 seeds",
                                tol)
                  : fmt::format("not decided at {} %: the intervals straddle it (about {} seeds would decide it, if "
                                "the spread so far holds)",
                                tol, needed);
  }
  const bool peak = r.peak_force.difference.resolved(), contact = r.max_contact_force.difference.resolved();
  line += peak || contact ? fmt::format("; the difference exceeds the seed-to-seed spread on {}",
                                        peak && contact ? "both" : peak ? "the peak force" : "the contact force")
                          : "; neither difference exceeds the seed-to-seed spread";
  return line;
}

}  // namespace

std::string percent_interval(const MeanInterval& d) {
  if (d.n == 0) return "-";
  if (!std::isfinite(d.half_width)) return fmt::format("{:+.1f}", 100.0 * d.mean);
  return fmt::format("{:+.1f} +- {:.1f}", 100.0 * d.mean, 100.0 * d.half_width);
}

std::string speedup_text(double s) { return s > 0.0 ? fmt::format("{:.2f}x", s) : "-"; }

ForceUnit force_unit(double largest_newtons) { return largest_newtons >= 1e3 ? ForceUnit{1e-3, "kN"} : ForceUnit{}; }

std::vector<std::uint64_t> parse_seeds(const std::string& text, const std::string& option) {
  const auto refuse = [&](const std::string& why) {
    throw config::ConfigError(fmt::format("{} '{}': {} (expected e.g. 1-5, 1,3,7 or 2-4,9)", option, text, why));
  };
  const auto whole = [&](const std::string& s) {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 18)
      refuse(fmt::format("'{}' is not a whole number >= 0", s));
    return std::stoull(s);
  };
  std::vector<std::uint64_t> seeds;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) {
    const auto dash = part.find('-', 1);
    if (dash == std::string::npos) {
      seeds.push_back(whole(part));
      continue;
    }
    const std::uint64_t first = whole(part.substr(0, dash)), last = whole(part.substr(dash + 1));
    if (last < first) refuse(fmt::format("the range {} runs backwards", part));
    if (last - first > 100000) refuse(fmt::format("the range {} holds more than 100,000 seeds", part));
    for (std::uint64_t s = first; s <= last; ++s) seeds.push_back(s);
  }
  if (seeds.empty()) refuse("no seed given");
  std::set<std::uint64_t> seen;
  for (auto s : seeds)
    if (!seen.insert(s).second) refuse(fmt::format("seed {} is given twice", s));
  return seeds;
}

std::vector<std::string> run_keys(const CompareRequest& request) {
  std::vector<std::string> keys;
  for (std::uint64_t seed : request.seeds)
    for (std::size_t m = 0; m < request.models.size(); ++m)
      keys.push_back(run_key(request.config_of(m), request.models[m], seed));
  return keys;
}

std::vector<std::size_t> seed_order(const std::vector<bool>& seed_incomplete, std::size_t first_seed) {
  std::vector<std::size_t> incomplete, complete;
  for (std::size_t s = 0; s < seed_incomplete.size(); ++s) (seed_incomplete[s] ? incomplete : complete).push_back(s);
  if (!incomplete.empty())
    std::rotate(incomplete.begin(), incomplete.begin() + std::ptrdiff_t(first_seed % incomplete.size()), incomplete.end());
  incomplete.insert(incomplete.end(), complete.begin(), complete.end());
  return incomplete;
}

void run_compare(runs::RunStore& store, const CompareRequest& request, const RunContext& context,
                 const std::function<void()>& after_run, std::size_t first_seed, const RunSlice& slice) {
  const std::size_t models = request.models.size();
  const std::vector<std::string> keys = run_keys(request);
  std::vector<bool> incomplete(request.seeds.size(), false);
  for (std::size_t k = 0; k < keys.size(); ++k)
    if (!store.has(keys[k])) incomplete[k / models] = true;
  for (const std::size_t seed : seed_order(incomplete, first_seed)) {
    for (std::size_t m = 0; m < models; ++m) {
      if (!slice.holds(seed * models + m)) continue;  // run_keys order
      ensure_push_run(store, request.config_of(m), request.models[m], request.seeds[seed], context);
      if (after_run) after_run();
    }
  }
}

CompareTable compare_table(const runs::RunStore& store, const CompareRequest& request) {
  CompareTable table;
  table.config = request.config.name;
  table.seeds = request.seeds;
  table.tolerance = request.tolerance;
  const std::size_t n_models = request.models.size(), n_seeds = request.seeds.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // value[m][s] of one number; NaN where the run is missing or failed.
  std::vector<std::vector<std::optional<runs::RunRecord>>> records(n_models,
                                                                   std::vector<std::optional<runs::RunRecord>>(n_seeds));
  std::set<std::string> revisions;
  std::vector<double> deposition;
  for (std::size_t m = 0; m < n_models; ++m)
    for (std::size_t s = 0; s < n_seeds; ++s) {
      records[m][s] = store.find(run_key(request.config_of(m), request.models[m], request.seeds[s]));
      if (records[m][s]) revisions.insert(records[m][s]->revision);
    }
  const auto values = [&](std::size_t m, const char* name) {
    std::vector<double> v(n_seeds, nan);
    for (std::size_t s = 0; s < n_seeds; ++s)
      if (records[m][s] && records[m][s]->finished()) v[s] = records[m][s]->number(name).value_or(nan);
    return v;
  };
  const auto finite_mean = [](const std::vector<double>& v) {
    std::vector<double> f;
    for (double x : v)
      if (std::isfinite(x)) f.push_back(x);
    return mean_of(f);
  };
  const std::size_t ref = request.reference;
  for (std::size_t s = 0; s < n_seeds; ++s)
    if (records[ref][s] && records[ref][s]->finished())
      deposition.push_back(records[ref][s]->number(number::kDepositionWall).value_or(0.0));
  table.deposition_wall = mean_of(deposition);
  table.revisions.assign(revisions.begin(), revisions.end());

  // The reference's curves, read once.
  std::vector<std::optional<railway::ForceCurve>> reference_curves(n_seeds);
  for (std::size_t s = 0; s < n_seeds; ++s)
    if (records[ref][s] && records[ref][s]->finished() && fs::exists(store.run_folder(records[ref][s]->key) / "push.h5"))
      reference_curves[s] = railway::read_force_curve(store.run_folder(records[ref][s]->key) / "push.h5");

  const double ref_push = finite_mean(values(ref, number::kPushWall));
  const double ref_total = ref_push + finite_mean(values(ref, number::kPreparationWall));
  for (std::size_t m = 0; m < n_models; ++m) {
    ModelRow row;
    row.model = request.label_of(m);
    row.reference = m == ref;
    for (std::size_t s = 0; s < n_seeds; ++s) {
      if (!records[m][s]) continue;
      if (records[m][s]->finished()) ++row.seeds;
      else {
        ++row.failed;
        row.failures.push_back(fmt::format("seed {}: {}", request.seeds[s], records[m][s]->message));
      }
    }
    row.clumps = finite_mean(values(m, number::kClumps));
    row.balls = finite_mean(values(m, number::kBalls));
    row.elements = finite_mean(values(m, number::kElements));
    row.contacts_at_peak = finite_mean(values(m, number::kContactsAtPeak));
    row.preparation_wall = finite_mean(values(m, number::kPreparationWall));
    row.push_wall = finite_mean(values(m, number::kPushWall));
    row.time_step = finite_mean(values(m, number::kTimeStep));
    row.steps = finite_mean(values(m, number::kSteps));
    if (row.elements > 0.0) row.contacts_per_element = row.contacts_at_peak / row.elements;
    if (row.push_wall > 0.0) row.element_steps_per_second = row.elements * row.steps / row.push_wall;
    if (row.push_wall > 0.0) row.push_speedup = ref_push / row.push_wall;
    if (row.push_wall + row.preparation_wall > 0.0) row.total_speedup = ref_total / (row.push_wall + row.preparation_wall);
    const auto output = [&](const char* name) {
      OutputRow o;
      o.mean = finite_mean(values(m, name));
      o.per_seed = relative_differences(values(m, name), values(ref, name));
      o.difference = mean_interval(o.per_seed);
      return o;
    };
    row.peak_force = output(number::kPeakForce);
    row.max_contact_force = output(number::kMaxContactForce);
    row.contact_force_q999 = output(number::kContactForceQ999);
    row.mean_force = output(number::kMeanForce);
    std::vector<double> curve_differences;
    for (std::size_t s = 0; s < n_seeds; ++s) {
      if (!reference_curves[s] || !records[m][s] || !records[m][s]->finished()) continue;
      if (m == ref) {  // its own curve: 0, not read again
        curve_differences.push_back(0.0);
        continue;
      }
      const fs::path push = store.run_folder(records[m][s]->key) / "push.h5";
      if (!fs::exists(push)) continue;  // a record without its curve (a store copied without the files)
      const railway::ForceCurve c = railway::read_force_curve(push);
      curve_differences.push_back(
          normalised_rms_difference(c.u, c.force, reference_curves[s]->u, reference_curves[s]->force));
    }
    row.curve_difference = mean_interval(curve_differences);
    row.peak_verdict = verdict(row.peak_force.difference, request.tolerance);
    row.contact_verdict = verdict(row.max_contact_force.difference, request.tolerance);
    table.rows.push_back(row);
  }
  const double reference_rate = table.rows[ref].element_steps_per_second;
  for (auto& row : table.rows)
    if (row.element_steps_per_second > 0.0 && reference_rate > 0.0)
      row.relative_step_cost = reference_rate / row.element_steps_per_second;
  return table;
}

void print_compare_table(std::ostream& out, const CompareTable& t) {
  std::size_t width = std::string("model").size();
  for (const auto& r : t.rows) width = std::max(width, r.model.size());
  std::string reference = "-";
  for (const auto& r : t.rows)
    if (r.reference) reference = r.model;
  fmt::print(out, "\nCompare: {} on seeds {} ({} seed{}); the reference is {}\n", t.config, fmt::join(t.seeds, ","),
             t.seeds.size(), t.seeds.size() == 1 ? "" : "s", reference);
  fmt::print(out, "\nCost (means over seeds; the shared deposition took {} per seed)\n",
             scene::format_duration(t.deposition_wall));
  fmt::print(out, "  {:<{}} {:>5} {:>6} {:>6} {:>9} {:>10} {:>12} {:>10} {:>8} {:>8}\n", "model", width, "runs", "clumps",
             "balls", "elements", "contacts", "re-settling", "push", "push x", "total x");
  for (const auto& r : t.rows)
    fmt::print(out, "  {:<{}} {:>5} {:>6.0f} {:>6.0f} {:>9.0f} {:>10.0f} {:>12} {:>10} {:>8} {:>8}\n", r.model, width,
               r.failed ? fmt::format("{}+{}F", r.seeds, r.failed) : std::to_string(r.seeds), r.clumps, r.balls,
               r.elements, r.contacts_at_peak, scene::format_duration(r.preparation_wall),
               scene::format_duration(r.push_wall), speedup_text(r.push_speedup), speedup_text(r.total_speedup));
  fmt::print(out, "\nCost of a push step (means over seeds)\n");
  fmt::print(out, "  {:<{}} {:>11} {:>9} {:>16} {:>18} {:>20}\n", "model", width, "time step", "steps",
             "element-steps/s", "contacts/element", "cost/element-step");
  for (const auto& r : t.rows)
    fmt::print(out, "  {:<{}} {:>11} {:>9.0f} {:>16} {:>18.2f} {:>20}\n", r.model, width,
               r.time_step > 0.0 ? fmt::format("{:.3g} s", r.time_step) : "-", r.steps,
               r.element_steps_per_second > 0.0 ? fmt::format("{:.3g}", r.element_steps_per_second) : "-",
               r.contacts_per_element, r.relative_step_cost > 0.0 ? fmt::format("{:.2f}x", r.relative_step_cost) : "-");
  fmt::print(out, "\nAccuracy (means over seeds; difference from the reference in %, paired by seed, +- the 95 % "
                  "Student-t half-width)\n");
  double largest = 0.0;
  for (const auto& r : t.rows) largest = std::max(largest, r.peak_force.mean);
  const auto [scale, unit] = force_unit(largest);
  fmt::print(out, "  {:<{}} {:>9} {:>15} {:>10} {:>15} {:>10} {:>15} {:>10} {:>15} {:>13}\n", "model", width,
             fmt::format("peak {}", unit), "d peak %", fmt::format("max c. {}", unit), "d max c. %",
             fmt::format("q99.9 {}", unit), "d q99.9 %", fmt::format("mean F {}", unit), "d mean F %", "F(u) NRMS %");
  for (const auto& r : t.rows)
    fmt::print(out, "  {:<{}} {:>9.4g} {:>15} {:>10.4g} {:>15} {:>10.4g} {:>15} {:>10.4g} {:>15} {:>13}\n", r.model,
               width, r.peak_force.mean * scale, percent_interval(r.peak_force.difference),
               r.max_contact_force.mean * scale, percent_interval(r.max_contact_force.difference),
               r.contact_force_q999.mean * scale, percent_interval(r.contact_force_q999.difference),
               r.mean_force.mean * scale, percent_interval(r.mean_force.difference),
               r.reference ? std::string("0") : percent_interval(r.curve_difference));
  fmt::print(out, "\nVerdict (peak lateral force and maximum contact force, tolerance {:.0f} %)\n", 100.0 * t.tolerance);
  for (const auto& r : t.rows) fmt::print(out, "  {:<{}}  {}\n", r.model, width, verdict_line(r, t.tolerance));
  for (const auto& r : t.rows)
    for (const auto& f : r.failures) fmt::print(out, "  failed: {} {}\n", r.model, f);
  fmt::print(out,
             "\nre-settling: the model's preparation after the shared deposition (conversion, growth of the balls, "
             "the later stages); push x, total x: the reference's wall time over the model's (push alone; "
             "re-settling + push). contacts: active element contacts at the peak. cost/element-step: the push's wall time per element-step against the reference's (above 1: an element of the model costs more). F(u) NRMS: RMS of F_model - "
             "F_reference over the reference's samples / its peak. An interval is over the seeds both models "
             "finished (t with n - 1 degrees of freedom); one seed gives no interval.\n");
  if (t.revisions.size() > 1)
    fmt::print(out, "WARNING: the runs were computed by {} code revisions ({}): the table mixes them\n",
               t.revisions.size(), fmt::join(t.revisions, ", "));
}

void write_compare_markdown(const fs::path& file, const CompareTable& t) {
  std::ofstream out(file);
  out << fmt::format("# Compare: {} on seeds {}\n\n", t.config, fmt::join(t.seeds, ","));
  out << "| model | runs | clumps | balls | elements | contacts at peak | re-settling (s) | push (s) | push speedup | "
         "total speedup | peak F (kN) | d peak (%) | max contact (kN) | d max contact (%) | q99.9 (kN) | d q99.9 (%) | "
         "mean F (kN) | d mean F (%) | F(u) NRMS (%) | verdict |\n";
  out << "|";
  for (int column = 0; column < 20; ++column) out << "---|";
  out << "\n";
  for (const auto& r : t.rows)
    out << fmt::format("| {} | {} | {:.0f} | {:.0f} | {:.0f} | {:.0f} | {:.1f} | {:.1f} | {} | {} | {:.4g} | {} | {:.4g} | "
                       "{} | {:.4g} | {} | {:.4g} | {} | {} | {} |\n",
                       r.model, r.seeds, r.clumps, r.balls, r.elements, r.contacts_at_peak, r.preparation_wall,
                       r.push_wall, speedup_text(r.push_speedup), speedup_text(r.total_speedup),
                       r.peak_force.mean * 1e-3, percent_interval(r.peak_force.difference),
                       r.max_contact_force.mean * 1e-3, percent_interval(r.max_contact_force.difference),
                       r.contact_force_q999.mean * 1e-3, percent_interval(r.contact_force_q999.difference),
                       r.mean_force.mean * 1e-3, percent_interval(r.mean_force.difference),
                       r.reference ? std::string("0") : percent_interval(r.curve_difference),
                       verdict_line(r, t.tolerance));
  out << "\n| model | time step (s) | push steps | contacts per element | element-steps per s | cost per element-step |\n"
         "|---|---|---|---|---|---|\n";
  for (const auto& r : t.rows)
    out << fmt::format("| {} | {:.3g} | {:.0f} | {:.2f} | {:.3g} | {:.2f}x |\n", r.model, r.time_step, r.steps,
                       r.contacts_per_element, r.element_steps_per_second, r.relative_step_cost);
  out << fmt::format("\nDifferences are paired by seed (every model starts from the seed's deposition): mean +- the "
                     "half-width of the 95 % Student-t interval over the seeds. The shared deposition took {:.1f} s "
                     "per seed.\n",
                     t.deposition_wall);
  if (t.revisions.size() > 1) out << fmt::format("\n**The runs mix code revisions: {}.**\n", fmt::join(t.revisions, ", "));
}

void write_compare_csv(const fs::path& file, const CompareTable& t) {
  // The four outputs, named once for the header and the rows.
  static constexpr std::pair<const char*, OutputRow ModelRow::*> kOutputs[] = {
      {"peak_force", &ModelRow::peak_force},
      {"max_contact_force", &ModelRow::max_contact_force},
      {"contact_force_q999", &ModelRow::contact_force_q999},
      {"mean_force", &ModelRow::mean_force}};
  std::ofstream out(file);
  out << "model,reference,seeds,failed,clumps,balls,elements,contacts_at_peak,preparation_wall_s,push_wall_s,"
         "push_speedup,total_speedup";
  for (const auto& [name, member] : kOutputs) out << fmt::format(",{0}_N,{0}_diff,{0}_diff_low,{0}_diff_high", name);
  out << ",curve_nrms,curve_nrms_low,curve_nrms_high,peak_verdict,contact_verdict,time_step_s,steps,"
         "contacts_per_element,element_steps_per_s,relative_step_cost";
  // Each seed's paired difference, space-separated in one field: with few seeds they say more
  // than an interval with n - 1 degrees of freedom (the speedup-error figure draws them).
  for (const auto& [name, member] : kOutputs) out << fmt::format(",{}_diff_per_seed", name);
  out << '\n';
  const auto g = [](double v) { return std::isfinite(v) ? fmt::format("{:.10g}", v) : std::string(); };
  for (const auto& r : t.rows) {
    out << fmt::format("\"{}\",{},{},{},{},{},{},{},{},{},{},{}", r.model, r.reference ? 1 : 0, r.seeds, r.failed,
                       g(r.clumps), g(r.balls), g(r.elements), g(r.contacts_at_peak), g(r.preparation_wall),
                       g(r.push_wall), g(r.push_speedup), g(r.total_speedup));
    for (const auto& [name, member] : kOutputs) {
      const OutputRow& o = r.*member;
      out << fmt::format(",{},{},{},{}", g(o.mean), g(o.difference.mean), g(o.difference.low()), g(o.difference.high()));
    }
    out << fmt::format(",{},{},{},{},{}", g(r.curve_difference.mean), g(r.curve_difference.low()),
                       g(r.curve_difference.high()), verdict_text(r.peak_verdict), verdict_text(r.contact_verdict));
    out << fmt::format(",{},{},{},{},{}", g(r.time_step), g(r.steps), g(r.contacts_per_element),
                       g(r.element_steps_per_second), g(r.relative_step_cost));
    for (const auto& [name, member] : kOutputs) {
      std::vector<std::string> seeds;
      for (double d : (r.*member).per_seed) seeds.push_back(g(d));
      out << fmt::format(",{}", fmt::join(seeds, " "));
    }
    out << '\n';
  }
}

}  // namespace mfdem::campaigns
