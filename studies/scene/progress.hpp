#pragma once
// A one-line progress report with an ETA on stderr: redrawn at most once a second on a terminal,
// a new line at most every 30 s into a file or a pipe (a log stays readable).
#include <chrono>
#include <filesystem>
#include <optional>
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
  bool mirrored_ = false;  // made while a ProgressMirror lives
  std::chrono::steady_clock::time_point start_, last_;
};

std::string format_duration(double seconds);

// While one lives, every Progress made meanwhile in this process, quiet or not, also writes its
// line ("settle 34 %") to `file`, replaced whole: a new stage's first line at once, then at most
// every 2 s; the file is removed when the mirror ends.
// A study's processes run quietly; the one that reports reads their runs' lines from these files.
class ProgressMirror {
 public:
  explicit ProgressMirror(std::filesystem::path file);
  ~ProgressMirror();
  ProgressMirror(const ProgressMirror&) = delete;
  ProgressMirror& operator=(const ProgressMirror&) = delete;

 private:
  std::optional<std::filesystem::path> replaced_;  // the mirror active before this one, restored after
};

// The line a mirror last wrote to `file`; empty when there is none.
std::string read_progress_mirror(const std::filesystem::path& file);

}  // namespace mfdem::scene
