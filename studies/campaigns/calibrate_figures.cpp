#include "studies/campaigns/calibrate_figures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "calibration/posterior.hpp"
#include "dem/hdf5_io.hpp"

namespace mfdem::campaigns {
namespace {

namespace h5 = dem::h5;

std::vector<double> axis(const CalibrationParameter& p, int n) {
  std::vector<double> v;
  for (int k = 0; k < n; ++k) v.push_back(p.lower + (p.upper - p.lower) * k / (n - 1));
  return v;
}

}  // namespace

void write_calibration_figure_data(const std::filesystem::path& path, const std::string& config_name,
                                   const CalibrateRequest& request, const CalibrateResult& result, int grid_points) {
  const calibration::MisfitSurrogate& s = *result.surrogate;
  const auto d = static_cast<Eigen::Index>(request.parameters.size());
  const std::vector<double> xs = axis(request.parameters[0], d == 1 ? 201 : grid_points);
  const std::vector<double> ys = d >= 2 ? axis(request.parameters[1], grid_points) : std::vector<double>{0.0};
  std::optional<calibration::MisfitSurrogate> expensive_only;
  std::vector<calibration::Evaluation> expensive_runs;
  for (const auto& r : result.loop.runs)
    if (r.level == calibration::Level::expensive) expensive_runs.push_back(r);
  if (s.two_levels()) {
    expensive_only.emplace(s.bounds(), s.targets(), s.kind(), s.search());
    expensive_only->fit(expensive_runs);
  }
  const std::vector<double> target_sd = {result.target_sd[0], result.target_sd[1]};
  std::vector<double> misfit, log_posterior, peak, contact, misfit_expensive;
  for (double y : ys)
    for (double x : xs) {
      Eigen::VectorXd p = result.calibrated;
      p(0) = x;
      if (d >= 2) p(1) = y;
      const auto outputs = s.predict_outputs(p);
      misfit.push_back(s.predict(p).mean);
      peak.push_back(outputs[0].mean);
      contact.push_back(outputs[1].mean);
      log_posterior.push_back(calibration::log_likelihood(s, p, target_sd));
      if (expensive_only) misfit_expensive.push_back(expensive_only->predict(p).mean);
    }
  const double top = *std::max_element(log_posterior.begin(), log_posterior.end());
  std::vector<double> posterior;
  for (double l : log_posterior) posterior.push_back(std::exp(l - top));

  h5::write_file(path, [&](hid_t file) {
    std::vector<std::string> names;
    for (const auto& p : request.parameters) names.push_back(p.name);
    h5::write_attribute(file, "config", config_name);
    h5::write_attribute(file, "policy", request.policy);
    h5::write_attribute(file, "parameter_names", names);
    h5::write_attribute(file, "target_peak", result.targets[0]);
    h5::write_attribute(file, "target_contact", result.targets[1]);
    h5::write_attribute(file, "seeds", double(request.seeds.size()));
    h5::write_attribute(file, "contact_quantile", request.contact_quantile ? 1.0 : 0.0);

    std::vector<double> lower, upper, calibrated, low, median, high;
    for (Eigen::Index k = 0; k < d; ++k) {
      lower.push_back(request.parameters[k].lower), upper.push_back(request.parameters[k].upper);
      calibrated.push_back(result.calibrated(k));
      low.push_back(result.posterior.intervals[k].lower), median.push_back(result.posterior.intervals[k].median);
      high.push_back(result.posterior.intervals[k].upper);
    }
    const hid_t pg = h5::make_group(file, "parameters");
    if (const auto truth = reference_parameters(request))
      h5::write_doubles(pg, "truth", std::vector<double>(truth->data(), truth->data() + truth->size()));
    for (const auto& [name, v] : {std::pair{"lower", &lower}, {"upper", &upper}, {"calibrated", &calibrated},
                                  {"interval_low", &low}, {"median", &median}, {"interval_high", &high}})
      h5::write_doubles(pg, name, *v);
    H5Gclose(pg);

    const hid_t g = h5::make_group(file, "grid");
    h5::write_doubles(g, "x", xs);
    if (d >= 2) h5::write_doubles(g, "y", ys);
    const hsize_t ny = d >= 2 ? ys.size() : 1, nx = xs.size();
    for (const auto& [name, v] : {std::pair{"misfit", &misfit}, {"posterior", &posterior}, {"peak", &peak},
                                  {"contact", &contact}})
      h5::write_doubles(g, name, v->data(), ny, nx);
    if (expensive_only) h5::write_doubles(g, "misfit_expensive_only", misfit_expensive.data(), ny, nx);
    H5Gclose(g);

    const auto& runs = result.loop.runs;
    std::vector<double> parameters, level, run_peak, run_contact, run_misfit;
    for (const auto& r : runs) {
      for (Eigen::Index k = 0; k < d; ++k) parameters.push_back(r.parameters(k));
      level.push_back(r.level == calibration::Level::cheap ? 0.0 : 1.0);
      run_peak.push_back(r.outputs(0)), run_contact.push_back(r.outputs(1));
      run_misfit.push_back(calibration::misfit(r.outputs, s.targets()));
    }
    const hid_t rg = h5::make_group(file, "runs");
    h5::write_doubles(rg, "parameters", parameters.data(), runs.size(), static_cast<hsize_t>(d));
    for (const auto& [name, v] : {std::pair{"level", &level}, {"peak", &run_peak}, {"contact", &run_contact},
                                  {"misfit", &run_misfit}})
      h5::write_doubles(rg, name, *v);
    H5Gclose(rg);

    std::vector<double> cost, returned, predicted, improvement;
    for (const auto& h : result.loop.history) {
      cost.push_back(h.cost), predicted.push_back(h.predicted_misfit), improvement.push_back(h.expected_improvement);
      for (Eigen::Index k = 0; k < d; ++k) returned.push_back(h.returned(k));
    }
    const hid_t hg = h5::make_group(file, "history");
    h5::write_doubles(hg, "cost", cost);
    h5::write_doubles(hg, "returned", returned.data(), result.loop.history.size(), static_cast<hsize_t>(d));
    h5::write_doubles(hg, "predicted_misfit", predicted);
    h5::write_doubles(hg, "expected_improvement", improvement);
    H5Gclose(hg);
  });
}

}  // namespace mfdem::campaigns
