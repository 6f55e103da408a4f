#pragma once
// What `mfdem calibrate` prints and writes: the calibrated parameters with their intervals, the
// outputs predicted there against the targets, the check on fresh seeds, the cost and the
// convergence (Markdown, readable in a terminal too), and one CSV row per candidate.
#include <filesystem>
#include <ostream>
#include <string>

#include "studies/campaigns/calibrate.hpp"

namespace mfdem::campaigns {

void write_calibration_markdown(std::ostream& out, const std::string& title, const CalibrateRequest& request,
                                const CalibrateResult& result);

// candidate, level, the parameters, peak_force, contact_force (means over the seeds), misfit.
void write_calibration_csv(const std::filesystem::path& file, const CalibrateRequest& request,
                           const CalibrateResult& result);

}  // namespace mfdem::campaigns
