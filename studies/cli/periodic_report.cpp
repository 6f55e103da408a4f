#include "studies/cli/periodic_report.hpp"

#include <chrono>

namespace mfdem::cli {

PeriodicReport::PeriodicReport(std::function<void()> report, bool enabled) : report_(std::move(report)) {
  if (!enabled) {
    report_ = nullptr;
    return;
  }
  thread_ = std::thread([this] {
    std::unique_lock lock(waiting_);
    while (!stop_signal_.wait_for(lock, std::chrono::seconds(1), [this] { return stopping_; })) now();
  });
}

PeriodicReport::~PeriodicReport() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard lock(waiting_);
    stopping_ = true;
  }
  stop_signal_.notify_all();
  thread_.join();
}

void PeriodicReport::now() {
  if (!report_) return;
  const std::lock_guard lock(reporting_);
  report_();
}

}  // namespace mfdem::cli
