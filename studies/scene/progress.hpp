#pragma once
// A one-line progress report with an ETA on stderr: redrawn at most once a second on a terminal,
// a new line at most every 30 s into a file or a pipe (a log stays readable).
#include <chrono>
#include <string>

namespace mfdem::scene {

class Progress {
 public:
  Progress(std::string label, double total, bool quiet);
  // `done` in the same unit as `total` (e.g. simulated seconds).
  void update(double done, const std::string& detail = "");
  void finish();

 private:
  std::string label_;
  double total_;
  bool quiet_;
  bool terminal_ = true;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

std::string format_duration(double seconds);

}  // namespace mfdem::scene
