#include "dem/spatial_order.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>

namespace mfdem::dem {
namespace {

// The low 21 bits of v, spread to every third bit.
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffffULL;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

}  // namespace

std::vector<Index> morton_order(const std::vector<Vec3>& points, double cell) {
  if (!(cell > 0.0)) throw std::invalid_argument("morton_order: the cell size must be > 0");
  std::vector<Index> order(points.size());
  std::iota(order.begin(), order.end(), Index{0});
  if (points.empty()) return order;
  Vec3 low = points.front();
  for (const Vec3& p : points) low = low.cwiseMin(p);
  constexpr double kLargestCell = (1 << 21) - 1;
  std::vector<std::uint64_t> code(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    std::uint64_t c = 0;
    for (int a = 0; a < 3; ++a) {
      const double q = std::min(std::floor((points[k][a] - low[a]) / cell), kLargestCell);
      c |= spread_bits(static_cast<std::uint64_t>(q)) << a;
    }
    code[k] = c;
  }
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return code[a] < code[b]; });
  return order;
}

}  // namespace mfdem::dem
