// The admissible interval of a numeric setting, e.g. {.min = 0, .min_exclusive = true} for a
// stiffness (N/m) that must be > 0. Unset bounds are open to infinity.
#pragma once

#include <optional>
#include <string>

namespace mfdem::config {

struct Range {
  std::optional<double> min{}, max{};
  bool min_exclusive = false, max_exclusive = false;
};

// True when x satisfies every bound of the range.
bool contains(const Range& range, double x);

// The bounds in words for a message: ">= 0", "> 0 and <= 1"; empty for an unbounded range.
std::string describe(const Range& range);

}  // namespace mfdem::config
