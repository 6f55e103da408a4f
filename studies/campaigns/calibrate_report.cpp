#include "studies/campaigns/calibrate_report.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cmath>
#include <fstream>

#include "calibration/misfit.hpp"

namespace mfdem::campaigns {
namespace {

std::string seeds_text(const std::vector<std::uint64_t>& seeds) {
  std::string s;
  for (auto seed : seeds) s += fmt::format("{}{}", s.empty() ? "" : ",", seed);
  return s;
}

std::string percent_interval(const MeanInterval& m) {
  if (m.n == 0) return "-";
  if (!std::isfinite(m.half_width)) return fmt::format("{:+.1f} % (1 seed)", 100.0 * m.mean);
  return fmt::format("{:+.1f} % +- {:.1f} %", 100.0 * m.mean, 100.0 * m.half_width);
}

}  // namespace

void write_calibration_markdown(std::ostream& out, const std::string& title, const CalibrateRequest& request,
                                const CalibrateResult& result) {
  fmt::print(out, "# {}\n\n", title);
  fmt::print(out, "Policy `{}`; every candidate on seeds {} (paired); reference: {}.\n\n", request.policy,
             seeds_text(request.seeds),
             request.reference ? std::string("the numbers given")
                               : fmt::format("`{}{}` on the same seeds", request.reference_model.policy,
                                             request.reference_model.rolling_friction
                                                 ? fmt::format(" mu_r={:g}", *request.reference_model.rolling_friction)
                                                 : std::string()));
  if (request.two_levels)
    fmt::print(out, "A cheap level ({}) informs the surrogates by co-kriging; a cheap candidate costs {:g} of an "
                    "expensive one.\n\n",
               fmt::format("{} {}", request.cheap_on_same_config ? "seeds" : "the cheap config on seeds",
                           seeds_text(request.seeds_at(calibration::Level::cheap)))
                   + (request.cheap_on_same_config ? " only" : ""),
               request.cheap_cost);
  const auto truth = reference_parameters(request);
  fmt::print(out, "| parameter | range | calibrated | 90 % interval | posterior median |{}\n|---|---|---|---|---|{}\n",
             truth ? " truth (the reference's) | calibrated - truth, % of the range |" : "", truth ? "---|---|" : "");
  for (std::size_t k = 0; k < request.parameters.size(); ++k) {
    const auto& p = request.parameters[k];
    const auto& i = result.posterior.intervals[k];
    const auto a = static_cast<Eigen::Index>(k);
    fmt::print(out, "| {} | {:g} - {:g} | {:.4g} | {:.4g} - {:.4g} | {:.4g} |{}\n", p.name, p.lower, p.upper,
               result.calibrated(a), i.lower, i.upper, i.median,
               truth ? fmt::format(" {:.4g} | {:+.1f} % |", (*truth)(a),
                                   100.0 * (result.calibrated(a) - (*truth)(a)) / (p.upper - p.lower))
                     : std::string());
  }
  const char* names[2] = {"peak lateral force",
                          request.contact_quantile ? "99.9 % quantile of the contact force" : "maximum contact force"};
  fmt::print(out, "\n| output | target (N) | predicted at the calibrated point (N) | error | on {} fresh seeds, paired |\n"
                  "|---|---|---|---|---|\n", result.verification.size());
  const MeanInterval* verified[2] = {&result.peak_difference, &result.contact_difference};
  for (int j = 0; j < 2; ++j) {
    const double sd = std::sqrt(result.predicted[j].variance);
    fmt::print(out, "| {} | {:.5g}{} | {:.5g} +- {:.2g} | {:+.1f} % | {} |\n", names[j], result.targets[j],
               result.target_sd[j] > 0 ? fmt::format(" +- {:.2g}", result.target_sd[j]) : "", result.predicted[j].mean,
               sd, 100.0 * (result.predicted[j].mean - result.targets[j]) / result.targets[j],
               percent_interval(*verified[j]));
  }
  if (request.verify_seeds.empty())
    fmt::print(out, "\nNot checked on fresh seeds (no --verify-seeds).\n\n");
  else
    fmt::print(out, "\nThe verified differences are (model - reference) / reference on seeds {} never used in the fit, "
                    "with the half-width of their 95 % Student-t interval.\n\n", seeds_text(request.verify_seeds));
  std::size_t cheap_candidates = 0;
  for (const auto& r : result.loop.runs) cheap_candidates += r.level == calibration::Level::cheap;
  fmt::print(out, "Cost: {} candidates{} ({} DEM runs of the model){}; stopped by {}.\n\n", result.loop.runs.size(),
             cheap_candidates ? fmt::format(" ({} of them cheap)", cheap_candidates) : std::string(), result.dem_runs,
             result.reference_wall > 0
                 ? fmt::format(", {:.1f} reference-run equivalents (their preparations and pushes over one "
                               "reference run's, {:.0f} s)", result.cost_in_reference_runs(), result.reference_wall)
                 : std::string(),
             result.loop.stopped_by);
  if (result.surrogate && result.surrogate->two_levels()) {
    // How much the cheap level carries: rho near 1 with a small delta is a cheap level that helps.
    const auto& models = result.surrogate->outputs();
    fmt::print(out, "The cheap level in the surrogates (co-kriging, y_expensive = rho y_cheap + delta):");
    for (std::size_t j = 0; j < models.size() && j < 2; ++j)
      fmt::print(out, "{} {}: rho = {:.3g}, run scatter (sd) cheap {:.3g} N, expensive {:.3g} N", j ? ";" : "",
                 j ? "contact" : "peak", models[j].scale_factor(), std::sqrt(models[j].cheap_noise_variance()),
                 std::sqrt(models[j].expensive_noise_variance()));
    fmt::print(out, ". `figures/misfit_surface.png` shows the misfit predicted with and without the cheap runs.\n\n");
  }
  fmt::print(out, "| step | cost (candidates) | returned point | predicted misfit | expected improvement |\n"
                  "|---|---|---|---|---|\n");
  for (std::size_t s = 0; s < result.loop.history.size(); ++s) {
    const auto& h = result.loop.history[s];
    std::string point;
    for (Eigen::Index a = 0; a < h.returned.size(); ++a) point += fmt::format("{}{:.4g}", a ? ", " : "", h.returned(a));
    fmt::print(out, "| {} | {:.2f} | {} | {:.3g} | {:.3g} |\n", s, h.cost, point, h.predicted_misfit,
               h.expected_improvement);
  }
}

void write_calibration_csv(const std::filesystem::path& file, const CalibrateRequest& request,
                           const CalibrateResult& result) {
  std::ofstream out(file);
  out << "candidate,level";
  for (const auto& p : request.parameters) out << "," << p.name;
  out << ",peak_force,contact_force,misfit\n";
  const std::vector<calibration::Target> targets = {calibration::relative_target(result.targets[0]),
                                                    calibration::relative_target(result.targets[1])};
  for (std::size_t k = 0; k < result.loop.runs.size(); ++k) {
    const auto& r = result.loop.runs[k];
    out << k << "," << (r.level == calibration::Level::cheap ? "cheap" : "expensive");
    for (Eigen::Index a = 0; a < r.parameters.size(); ++a) out << fmt::format(",{:.9g}", r.parameters(a));
    out << fmt::format(",{:.9g},{:.9g},{:.6g}\n", r.outputs(0), r.outputs(1), calibration::misfit(r.outputs, targets));
  }
}

}  // namespace mfdem::campaigns
