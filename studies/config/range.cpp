#include "studies/config/range.hpp"

#include <fmt/format.h>

namespace mfdem::config {

bool contains(const Range& range, double x) {
  if (range.min && (range.min_exclusive ? !(x > *range.min) : !(x >= *range.min))) return false;
  if (range.max && (range.max_exclusive ? !(x < *range.max) : !(x <= *range.max))) return false;
  return true;
}

std::string describe(const Range& range) {
  std::string lower = range.min ? fmt::format("{} {:.6g}", range.min_exclusive ? ">" : ">=", *range.min) : "";
  std::string upper = range.max ? fmt::format("{} {:.6g}", range.max_exclusive ? "<" : "<=", *range.max) : "";
  if (!lower.empty() && !upper.empty()) return lower + " and " + upper;
  return lower + upper;
}

}  // namespace mfdem::config
