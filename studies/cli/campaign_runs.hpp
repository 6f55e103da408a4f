#pragma once
// The DEM runs of the campaign commands that call a CandidateRunner (calibrate, optimise-layer):
// their run store, pushes and a line printed per run; and their reports.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>

#include "studies/campaigns/calibrate.hpp"
#include "studies/cli/version.hpp"

namespace mfdem::cli {

// Prints a line per DEM run (elapsed time, model, seed, the two outputs): they take minutes each.
class ReportingRunner final : public campaigns::CandidateRunner {
 public:
  ReportingRunner(campaigns::CandidateRunner& inner, const railway::PushStudyConfig& config, bool quiet)
      : inner_(inner), config_(config), quiet_(quiet), start_(std::chrono::steady_clock::now()) {}
  campaigns::RunOutputs run(const campaigns::Model& model, std::uint64_t seed, calibration::Level level) override {
    const auto out = inner_.run(model, seed, level);
    if (!quiet_)
      fmt::print(std::cerr, "  {:>7.0f} s  {}{} seed {}: peak {:.1f} N, contact {:.1f} N\n",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(), model.text(config_),
                 level == calibration::Level::cheap ? " (cheap)" : "", seed, out.peak_force, out.contact_force);
    return out;
  }

 private:
  campaigns::CandidateRunner& inner_;
  const railway::PushStudyConfig& config_;
  bool quiet_;
  std::chrono::steady_clock::time_point start_;
};

// The store in `out` (runs left by stopped processes cleared), pushes of `config` (and of `cheap`
// at the cheap level), each run reported unless quiet. `config` must outlive it.
struct CampaignRuns {
  CampaignRuns(const std::filesystem::path& out, const railway::PushStudyConfig& config,
               std::optional<railway::PushStudyConfig> cheap, bool contact_quantile, bool quiet)
      : store(out),
        pushes(store, config, std::move(cheap), campaigns::RunContext{git_revision()}, contact_quantile),
        runner(pushes, config, quiet) {
    store.clear_abandoned();
  }
  runs::RunStore store;
  campaigns::PushRunner pushes;
  ReportingRunner runner;
};

// A report formatted once, written to `file` and printed unless quiet.
inline void write_report(const std::filesystem::path& file, bool quiet, const std::function<void(std::ostream&)>& write) {
  std::ostringstream text;
  write(text);
  std::ofstream(file) << text.str();
  if (!quiet) std::cout << text.str();
}

}  // namespace mfdem::cli
