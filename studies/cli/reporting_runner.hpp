#pragma once
// A CandidateRunner that prints a line per DEM run (elapsed time, model, seed, the two outputs):
// the runs of calibrate and optimise-layer take minutes each.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <chrono>
#include <iostream>

#include "studies/campaigns/calibrate.hpp"

namespace mfdem::cli {

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

}  // namespace mfdem::cli
