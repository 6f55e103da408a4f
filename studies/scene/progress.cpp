#include "studies/scene/progress.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <cstdio>

namespace mfdem::scene {

std::string format_duration(double seconds) {
  if (seconds < 60.0) return fmt::format("{:.0f} s", seconds);
  if (seconds < 3600.0) return fmt::format("{:.0f} min {:02.0f} s", std::floor(seconds / 60.0), std::fmod(seconds, 60.0));
  return fmt::format("{:.0f} h {:02.0f} min", std::floor(seconds / 3600.0), std::fmod(seconds, 3600.0) / 60.0);
}

Progress::Progress(std::string label, double total, bool quiet)
    : label_(std::move(label)), total_(total), quiet_(quiet),
      terminal_(isatty(fileno(stderr)) != 0), start_(std::chrono::steady_clock::now()), last_(start_) {}

void Progress::update(double done, const std::string& detail) {
  if (quiet_) return;
  const auto now = std::chrono::steady_clock::now();
  // A terminal redraws one line every second; a file or a pipe (a log) gets a line every 30 s.
  if (drawn_ && now - last_ < std::chrono::seconds(terminal_ ? 1 : 30)) return;
  last_ = now;
  drawn_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double fraction = total_ > 0 ? std::min(1.0, done / total_) : 1.0;
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
