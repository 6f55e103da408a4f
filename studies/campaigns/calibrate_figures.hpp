#pragma once
// The numbers behind `mfdem calibrate`'s figures, written to OUT/calibration.h5 for
// studies/python/mfdem/calibrate_figures.py to draw (numbers computed here, only drawn there):
//
//   attrs: config, policy, parameter_names (comma-joined), target_peak, target_contact (N)
//   /parameters/{lower, upper, calibrated, interval_low, median, interval_high}   one per parameter
//   /parameters/truth          a synthetic truth's values (the reference model's), when it sets them
//   /grid/x, /grid/y           the first two parameters (y absent with one), any others held at
//                              their calibrated values
//   /grid/misfit               [ny, nx] predicted mean misfit (sum of squared relative errors)
//   /grid/posterior            [ny, nx] posterior density, scaled to a maximum of 1
//   /grid/peak, /grid/contact  [ny, nx] predicted outputs, N
//   /grid/misfit_expensive_only  [ny, nx] two-level studies: the misfit the expensive runs alone predict
//   /runs/{parameters [n, d], level (0 cheap, 1 expensive), peak, contact, misfit}
//   /history/{cost, returned [s, d], predicted_misfit, expected_improvement}
#include <filesystem>

#include "studies/campaigns/calibrate.hpp"

namespace mfdem::campaigns {

void write_calibration_figure_data(const std::filesystem::path& path, const std::string& config_name,
                                   const CalibrateRequest& request, const CalibrateResult& result, int grid_points = 61);

}  // namespace mfdem::campaigns
