#pragma once
// A study's progress line while its runs compute: `report` called about once a second from a
// thread of its own (a run in this process reports nothing between its stages) and whenever
// `now()` is called, never two calls at once.
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace mfdem::cli {

class PeriodicReport {
 public:
  // `enabled` false (a quiet or worker process): no thread, now() does nothing.
  PeriodicReport(std::function<void()> report, bool enabled);
  ~PeriodicReport();
  PeriodicReport(const PeriodicReport&) = delete;
  PeriodicReport& operator=(const PeriodicReport&) = delete;

  void now();

 private:
  std::function<void()> report_;
  std::mutex reporting_, waiting_;
  std::condition_variable stop_signal_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace mfdem::cli
