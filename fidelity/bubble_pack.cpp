#include "fidelity/bubble_pack.hpp"

#include <algorithm>
#include <cmath>
#include <queue>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace mfdem::fidelity {

namespace {

constexpr int min_grid_cells = 4;
constexpr int max_grid_cells = 400;

// Interior samples at cell centres, with their distance to the surface.
struct InteriorGrid {
  Vec3 origin;  // centre of cell (0, 0, 0)
  double cell = 0.0;
  Eigen::Array3i cells;
  std::vector<int> sample_of_cell;  // -1 outside the surface
  std::vector<Vec3> position;
  std::vector<double> clearance;  // distance to the surface

  int cell_index(int i, int j, int k) const { return (k * cells.y() + j) * cells.x() + i; }

  // Calls visit(sample) for every interior sample within `radius` of `centre`.
  template <class Visit>
  void for_each_within(const Vec3& centre, double radius, Visit&& visit) const {
    const Eigen::Array3d lo = ((centre.array() - radius - origin.array()) / cell).ceil();
    const Eigen::Array3d hi = ((centre.array() + radius - origin.array()) / cell).floor();
    const Eigen::Array3i first = lo.cast<int>().max(0);
    const Eigen::Array3i last = hi.cast<int>().min(cells - 1);
    const double r2 = radius * radius;
    for (int k = first.z(); k <= last.z(); ++k)
      for (int j = first.y(); j <= last.y(); ++j)
        for (int i = first.x(); i <= last.x(); ++i) {
          const int s = sample_of_cell[cell_index(i, j, k)];
          if (s >= 0 && (position[s] - centre).squaredNorm() <= r2) visit(s);
        }
  }
};

InteriorGrid sample_interior(const TriangleMesh& surface, int grid_cells) {
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 upper = -lower;
  for (const auto& v : surface.vertices) lower = lower.cwiseMin(v), upper = upper.cwiseMax(v);
  InteriorGrid grid;
  grid.cell = (upper - lower).maxCoeff() / grid_cells;
  grid.cells = ((upper - lower).array() / grid.cell).ceil().cast<int>().max(1);
  const Vec3 span = grid.cells.cast<double>() * grid.cell;
  grid.origin = (lower + upper) / 2.0 - span / 2.0 + Vec3::Constant(grid.cell / 2.0);
  grid.sample_of_cell.assign(grid.cells.prod(), -1);
  for (int k = 0; k < grid.cells.z(); ++k)
    for (int j = 0; j < grid.cells.y(); ++j)
      for (int i = 0; i < grid.cells.x(); ++i) {
        const Vec3 p = grid.origin + grid.cell * Vec3(i, j, k);
        if (!inside(surface, p)) continue;
        grid.sample_of_cell[grid.cell_index(i, j, k)] = static_cast<int>(grid.position.size());
        grid.position.push_back(p);
        grid.clearance.push_back(distance_to_surface(surface, p));
      }
  return grid;
}

std::vector<Pebble> largest_new_volume(const InteriorGrid& grid, const BubblePackOptions& options) {
  const int n = static_cast<int>(grid.position.size());
  std::vector<char> covered(n, 0);
  auto gain_of = [&](int c) {
    long long gain = 0;
    grid.for_each_within(grid.position[c], grid.clearance[c], [&](int s) { gain += !covered[s]; });
    return gain;
  };
  // Max-heap of (gain bound, -sample): ties go to the lowest sample index, for determinism.
  std::priority_queue<std::pair<long long, int>> heap;
  for (int c = 0; c < n; ++c)
    if (grid.clearance[c] >= options.min_radius) heap.emplace(gain_of(c), -c);
  std::vector<Pebble> pebbles;
  while (static_cast<int>(pebbles.size()) < options.pebbles && !heap.empty()) {
    const int c = -heap.top().second;
    heap.pop();
    const long long gain = gain_of(c);
    if (gain == 0) continue;
    if (!heap.empty() && std::make_pair(gain, -c) < heap.top()) {
      heap.emplace(gain, -c);  // stale bound: re-queue with the true gain
      continue;
    }
    pebbles.push_back({grid.position[c], grid.clearance[c]});
    grid.for_each_within(grid.position[c], grid.clearance[c], [&](int s) { covered[s] = 1; });
  }
  return pebbles;
}

std::vector<Pebble> farthest_point(const InteriorGrid& grid, const BubblePackOptions& options) {
  const int n = static_cast<int>(grid.position.size());
  std::vector<double> outside(n, std::numeric_limits<double>::infinity());  // distance outside the pebbles
  std::vector<Pebble> pebbles;
  while (static_cast<int>(pebbles.size()) < options.pebbles) {
    int best = -1;
    double best_score = 0.0;
    for (int s = 0; s < n; ++s) {
      if (grid.clearance[s] < options.min_radius) continue;
      const double score = std::min(grid.clearance[s], outside[s]);
      if (score > best_score) best_score = score, best = s;
    }
    if (best < 0) break;  // every admissible sample is covered
    const Pebble pebble{grid.position[best], grid.clearance[best]};
    pebbles.push_back(pebble);
    for (int s = 0; s < n; ++s) outside[s] = std::min(outside[s], (grid.position[s] - pebble.centre).norm() - pebble.radius);
  }
  return pebbles;
}

}  // namespace

std::vector<Pebble> bubble_pack(const TriangleMesh& surface, const BubblePackOptions& options) {
  if (options.pebbles < 1) throw std::invalid_argument(fmt::format("a clump needs at least one pebble (got {})", options.pebbles));
  if (options.grid_cells < min_grid_cells || options.grid_cells > max_grid_cells)
    throw std::invalid_argument(fmt::format("bubble-pack grid must have between {} and {} cells along the longest side (got {})",
                                            min_grid_cells, max_grid_cells, options.grid_cells));
  if (!(options.min_radius >= 0.0)) throw std::invalid_argument("the smallest pebble radius must be >= 0");
  const InteriorGrid grid = sample_interior(surface, options.grid_cells);
  if (grid.position.empty())
    throw std::invalid_argument("the surface encloses no sample of the bubble-pack grid; refine the grid");
  return options.rule == BubblePackRule::largest_new_volume ? largest_new_volume(grid, options)
                                                            : farthest_point(grid, options);
}

}  // namespace mfdem::fidelity
