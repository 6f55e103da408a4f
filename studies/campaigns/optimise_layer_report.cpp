#include "studies/campaigns/optimise_layer_report.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace mfdem::campaigns {
namespace {

std::string percent(const MeanInterval& m) {
  if (!std::isfinite(m.half_width)) return fmt::format("{:+.1f}", 100.0 * m.mean);
  return fmt::format("{:+.1f} +- {:.1f}", 100.0 * m.mean, 100.0 * m.half_width);
}

std::string extent_text(const FamilyFront& f, double extent) { return fmt::format("{}={:.4g}", f.extent_name, extent); }

// The family's candidates from the dearest to the cheapest.
std::vector<std::size_t> by_speedup(const OptimiseLayerResult& r) {
  std::vector<std::size_t> order(r.front.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return r.front[a].speedup < r.front[b].speedup; });
  return order;
}

std::string verdict(const FamilyFront& f, double tolerance) {
  const auto& r = f.result;
  if (r.chosen) {
    const auto& c = r.front[*r.chosen];
    // Judged at a coarser tolerance than asked when the seeds resolve no finer: say so here.
    const std::string within = c.tolerance_used > tolerance
                                   ? fmt::format("within {:.3g} % (the finest these seeds resolve; {:.3g} % asked)",
                                                 100.0 * c.tolerance_used, 100.0 * tolerance)
                                   : fmt::format("within {:.3g} %", 100.0 * tolerance);
    return fmt::format("{}: the cheapest {} is {}, mu_r = {:.3g}: speedup {:.2f}x (push {:.2f}x), peak {} %, contact {} %",
                       f.policy, within, extent_text(f, c.extent), c.rolling_friction, c.speedup, c.push_speedup,
                       percent(c.peak_error), percent(c.contact_error));
  }
  const auto order = by_speedup(r);
  if (order.empty()) return fmt::format("{}: nothing evaluated", f.policy);
  const auto& dearest = r.front[order.front()];
  return fmt::format("{}: no extent within {:.3g} %, even the dearest ({}: peak {} %, contact {} %)", f.policy,
                     100.0 * tolerance, extent_text(f, dearest.extent), percent(dearest.peak_error),
                     percent(dearest.contact_error));
}

void row(std::ostream& out, const std::string& family, const std::string& extent, const std::string& mu_r,
         const std::string& runs, const LayerCandidate& c, const std::string& mark) {
  fmt::print(out, "| {} | {} | {} | {} | {:.2f}x | {:.2f}x | {} | {} | {:.3g} | {}{} |\n", family, extent, mu_r, runs,
             c.speedup, c.push_speedup, percent(c.peak_error), percent(c.contact_error), 100.0 * c.tolerance_used,
             c.within ? "yes" : "no", mark);
}

}  // namespace

void write_optimise_markdown(std::ostream& out, const std::string& title, const OptimiseLayerRequest& request,
                             const std::vector<FamilyFront>& families, const std::vector<MeasuredModel>& uncalibrated) {
  fmt::print(out, "# {}\n\n", title);
  fmt::print(out, "Every candidate on seeds {} (paired with the reference `{}` on the same seeds); tolerance {:.3g} % on "
                  "both the peak lateral force and the {}.\n\n",
             fmt::join(request.seeds, ","), request.reference_model.policy, 100.0 * request.tolerance,
             request.contact_quantile ? "99.9 % quantile of the contact force" : "maximum contact force");
  for (const auto& f : families) fmt::print(out, "- {}\n", verdict(f, request.tolerance));
  const FamilyFront* best = nullptr;
  for (const auto& f : families)
    if (f.result.chosen && (!best || f.result.front[*f.result.chosen].speedup > best->result.front[*best->result.chosen].speedup))
      best = &f;
  if (families.size() > 1 && best)
    fmt::print(out, "- At {:.3g} %, {} is the cheaper family.\n", 100.0 * request.tolerance, best->policy);
  double resolvable = 0.0;
  int seeds_needed = 0;
  for (const auto& f : families)
    resolvable = std::max(resolvable, f.result.resolvable_tolerance),
    seeds_needed = std::max(seeds_needed, f.result.seeds_to_resolve);
  if (resolvable > request.tolerance)
    fmt::print(out, "- The seeds resolve no tolerance finer than {:.3g} % (twice the largest standard error of a paired "
                    "difference); candidates were judged at that. About {} seeds would resolve {:.3g} %.\n",
               100.0 * resolvable, seeds_needed, 100.0 * request.tolerance);

  fmt::print(out, "\n| family | extent | mu_r | runs at this extent | speedup | push speedup | d peak % | d contact % | "
                  "tolerance used % | within |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& f : families)
    for (auto k : by_speedup(f.result)) {
      const auto& c = f.result.front[k];
      row(out, f.policy, extent_text(f, c.extent), fmt::format("{:.3g}", c.rolling_friction),
          fmt::format("{}", c.runs_here), c, f.result.chosen == k ? " (chosen)" : "");
    }
  for (const auto& m : uncalibrated) row(out, m.model + " (uncalibrated)", "-", "-", "-", m.measured, "");
  fmt::print(out, "\nd peak, d contact: (model - reference) / reference, the mean over the seeds +- the half-width of its "
                  "95 % Student-t interval. speedup: the reference's preparation and push wall time over the model's "
                  "(push speedup: the push alone). mu_r is calibrated at each extent (the best of its runs there); "
                  "runs at this extent: candidates run to calibrate it (the shared design's runs not counted).\n\n");
  int runs = 0;
  double equivalents = 0.0;
  for (const auto& f : families) runs += f.result.dem_runs, equivalents += f.result.cost_in_reference_runs();
  fmt::print(out, "Cost: {} DEM runs of candidates, {:.1f} reference-run equivalents (their preparations and pushes "
                  "over one reference run's).\n", runs, equivalents);
}

void write_optimise_csv(const std::filesystem::path& file, const std::vector<FamilyFront>& families,
                        const std::vector<MeasuredModel>& uncalibrated) {
  std::ofstream out(file);
  out << "family,extent_name,extent,mu_r,calibrated,chosen,runs_here,speedup,push_speedup,peak_force,contact_force,"
         "peak_diff,peak_diff_half_width,contact_diff,contact_diff_half_width,tolerance_used,within\n";
  const auto line = [&](const std::string& family, const std::string& extent_name, double extent, double mu_r,
                        bool calibrated, bool chosen, int runs_here, const LayerCandidate& c) {
    out << fmt::format("\"{}\",{},{:.9g},{:.9g},{},{},{},{:.6g},{:.6g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{}\n",
                       family, extent_name, extent, mu_r, calibrated ? 1 : 0, chosen ? 1 : 0, runs_here, c.speedup,
                       c.push_speedup, c.mean.peak_force, c.mean.contact_force, c.peak_error.mean,
                       c.peak_error.half_width, c.contact_error.mean, c.contact_error.half_width, c.tolerance_used,
                       c.within ? 1 : 0);
  };
  for (const auto& f : families)
    for (std::size_t k = 0; k < f.result.front.size(); ++k) {
      const auto& c = f.result.front[k];
      line(f.policy, f.extent_name, c.extent, c.rolling_friction, true, f.result.chosen == k, c.runs_here, c);
    }
  for (const auto& m : uncalibrated) line(m.model, "", NAN, NAN, false, false, 0, m.measured);
}

}  // namespace mfdem::campaigns
