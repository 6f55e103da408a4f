#pragma once
// `mfdem optimise-layer`'s tables: Markdown (printed too) and CSV, one row per extent evaluated
// of every family, then the uncalibrated models; the chosen layer and its verdict first.
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "studies/campaigns/optimise_layer.hpp"

namespace mfdem::campaigns {

void write_optimise_markdown(std::ostream& out, const std::string& title, const OptimiseLayerRequest& request,
                             const std::vector<FamilyFront>& families, const std::vector<MeasuredModel>& uncalibrated);
void write_optimise_csv(const std::filesystem::path& file, const std::vector<FamilyFront>& families,
                        const std::vector<MeasuredModel>& uncalibrated);

}  // namespace mfdem::campaigns
