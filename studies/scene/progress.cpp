#include "studies/scene/progress.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>

namespace mfdem::scene {
namespace {

struct Mirror {
  std::filesystem::path file;
  std::chrono::steady_clock::time_point last;
  std::string label;  // of the line last written
  bool written = false;
};
std::optional<Mirror> active_mirror;  // one run at a time per process

void write_mirror(const std::string& label, double fraction) {
  if (!active_mirror) return;
  const auto now = std::chrono::steady_clock::now();
  // A new stage is shown at once; a stage's further lines at most every 2 s.
  if (active_mirror->written && label == active_mirror->label && now - active_mirror->last < std::chrono::seconds(2))
    return;
  active_mirror->last = now;
  active_mirror->label = label;
  active_mirror->written = true;
  // Written beside and renamed over: a reader never sees half a line. A failure only loses a line.
  std::filesystem::path temporary = active_mirror->file;
  temporary += ".new";
  std::string name = label;
  name.erase(name.find_last_not_of(' ') + 1);
  std::ofstream(temporary) << fmt::format("{} {:.0f} %\n", name, 100.0 * fraction);
  std::error_code ignored;
  std::filesystem::rename(temporary, active_mirror->file, ignored);
}

}  // namespace

ProgressMirror::ProgressMirror(std::filesystem::path file) {
  if (active_mirror) replaced_ = active_mirror->file;
  active_mirror = Mirror{std::move(file), {}, {}, false};
}

ProgressMirror::~ProgressMirror() {
  std::error_code ignored;
  if (active_mirror) std::filesystem::remove(active_mirror->file, ignored);
  active_mirror.reset();
  if (replaced_) active_mirror = Mirror{*replaced_, {}, {}, false};
}

std::string read_progress_mirror(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

std::string format_duration(double seconds) {
  if (seconds < 60.0) return fmt::format("{:.0f} s", seconds);
  if (seconds < 3600.0) return fmt::format("{:.0f} min {:02.0f} s", std::floor(seconds / 60.0), std::fmod(seconds, 60.0));
  return fmt::format("{:.0f} h {:02.0f} min", std::floor(seconds / 3600.0), std::fmod(seconds, 3600.0) / 60.0);
}

Progress::Progress(std::string label, double total, bool quiet)
    : label_(std::move(label)), total_(total), quiet_(quiet),
      terminal_(isatty(fileno(stderr)) != 0), mirrored_(active_mirror.has_value()),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

void Progress::update(double done, const std::string& detail) {
  const double fraction = total_ > 0 ? std::min(1.0, done / total_) : 1.0;
  if (mirrored_) write_mirror(label_, fraction);
  if (quiet_) return;
  const auto now = std::chrono::steady_clock::now();
  // A terminal redraws one line every second; a file or a pipe (a log) gets a line every 30 s.
  if (drawn_ && now - last_ < std::chrono::seconds(terminal_ ? 1 : 30)) return;
  last_ = now;
  drawn_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const std::string eta = fraction > 0.0 ? format_duration(elapsed * (1.0 - fraction) / fraction) : "?";
  fmt::print(stderr, "{}{} {:5.1f} %  elapsed {}  ETA {}  {}{}", terminal_ ? "\r" : "", label_, 100.0 * fraction,
             format_duration(elapsed), eta, detail, terminal_ ? "\033[K" : "\n");
  std::fflush(stderr);
}

void Progress::finish() {
  if (quiet_ || !drawn_ || !terminal_) return;
  fmt::print(stderr, "\n");
}

}  // namespace mfdem::scene
