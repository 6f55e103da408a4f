#include "dem/neighbor_list.hpp"

#include <fmt/format.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mfdem::dem {

PeriodicBoxTooShortError::PeriodicBoxTooShortError(int axis_, double length_, double shortest_)
    : std::invalid_argument(fmt::format("periodic box length along axis {} ({:.6g} m) must be at least 2 x "
                                        "(largest diameter + skin) = {:.6g} m",
                                        "xyz"[axis_], length_, shortest_)),
      axis(axis_),
      length(length_),
      shortest(shortest_) {}
namespace {

void finish_csr(PairList& list, Index element_count) {
  list.row_start.assign(element_count + 1, 0);
  for (Index p = 0; p < list.size(); ++p) ++list.row_start[list.first[p] + 1];
  for (Index e = 0; e < element_count; ++e) list.row_start[e + 1] += list.row_start[e];

  list.as_second_start.assign(element_count + 1, 0);
  for (Index p = 0; p < list.size(); ++p) ++list.as_second_start[list.second[p] + 1];
  for (Index e = 0; e < element_count; ++e) list.as_second_start[e + 1] += list.as_second_start[e];
  list.as_second_pair.resize(list.size());
  std::vector<Index> fill(list.as_second_start.begin(), list.as_second_start.end() - 1);
  for (Index p = 0; p < list.size(); ++p) list.as_second_pair[fill[list.second[p]]++] = p;
}

}  // namespace

// Cells are about one typical contact reach wide (2 x mean radius + skin), not one largest
// reach: in a graded bed (pebbles of 4-32 mm) cells sized for the largest pair made every
// element scan 27 large cells, about 60 times the volume its contacts can lie in. Each pair is
// found by its larger member, which scans the cells overlapping the cube of half-width
// 2 r_i + skin around itself.
PairList build_pair_list(const Elements& elements, const Domain& domain, double skin) {
  const Index n = elements.size();
  PairList list;
  if (n == 0) {
    finish_csr(list, 0);
    return list;
  }
  double largest = 0.0, radius_sum = 0.0;
  for (double r : elements.radius) {
    largest = std::max(largest, r);
    radius_sum += r;
  }
  const double cutoff = 2.0 * largest + skin;
  double cell_target = std::max(2.0 * radius_sum / n + skin, 0.25 * cutoff);
  const Vec3 length = domain.length();
  for (int a = 0; a < 3; ++a) {
    // Two largest reaches per periodic length: then at most one image of j is within reach of
    // i (two images lie a length apart, both within reach only if it is below 2 x reach), so a
    // scan that meets a cell twice through two images keeps at most one. A ball of equal volume
    // is wider than any pebble of its clump: three reaches did not fit mini's 0.2 m section.
    if (domain.periodic[a] && length[a] < shortest_periodic_length(largest, skin))
      throw PeriodicBoxTooShortError(a, length[a], shortest_periodic_length(largest, skin));
  }
  // A sparse scene in a large box (a few bodies in a tall domain) gets larger cells: at most
  // about eight cells per element, and never fewer than a million allowed.
  const double cell_limit = std::max(1e6, 8.0 * n);
  const double box_cells = (length[0] / cell_target) * (length[1] / cell_target) * (length[2] / cell_target);
  if (box_cells > cell_limit) cell_target *= std::cbrt(box_cells / cell_limit);
  std::array<int, 3> cells{};
  for (int a = 0; a < 3; ++a) cells[a] = std::max(1, static_cast<int>(std::floor(length[a] / cell_target)));
  const Vec3 cell_size(length[0] / cells[0], length[1] / cells[1], length[2] / cells[2]);

  // Bin wrapped positions; clamp along walled axes (clamping keeps near pairs adjacent).
  std::vector<Vec3> wrapped(n);
  std::vector<int> cell_of(n);
#pragma omp parallel for schedule(static) if (n > 4096)
  for (Index e = 0; e < n; ++e) {
    wrapped[e] = elements.position[e] + domain.wrap_shift(elements.position[e]);
    int c[3];
    for (int a = 0; a < 3; ++a) {
      const int k = static_cast<int>(std::floor((wrapped[e][a] - domain.min[a]) / cell_size[a]));
      c[a] = std::clamp(k, 0, cells[a] - 1);
    }
    cell_of[e] = (c[2] * cells[1] + c[1]) * cells[0] + c[0];
  }
  const int cell_count = cells[0] * cells[1] * cells[2];
  std::vector<Index> cell_start(cell_count + 1, 0);
  for (Index e = 0; e < n; ++e) ++cell_start[cell_of[e] + 1];
  for (int c = 0; c < cell_count; ++c) cell_start[c + 1] += cell_start[c];
  // The members of each cell, in element order, with copies of what the scan reads laid out in
  // cell order: the candidates of a cell are then contiguous in memory, not scattered.
  std::vector<Index> cell_members(n);
  {
    std::vector<Index> fill(cell_start.begin(), cell_start.end() - 1);
    for (Index e = 0; e < n; ++e) cell_members[fill[cell_of[e]]++] = e;
  }
  std::vector<Vec3> member_position(n);
  std::vector<double> member_radius(n);
  std::vector<Index> member_body(n);
#pragma omp parallel for schedule(static) if (n > 4096)
  for (Index m = 0; m < n; ++m) {
    const Index e = cell_members[m];
    member_position[m] = wrapped[e];
    member_radius[m] = elements.radius[e];
    member_body[m] = elements.body[e];
  }

  // The cells along one axis that element i scans, each with the periodic image it is reached
  // through (a cell reached across a periodic face holds images one box length away).
  struct AxisRange {
    int count = 0;
    std::array<int, 32> cell{};
    std::array<std::int8_t, 32> image{};
  };
  auto axis_range = [&](int a, double x, double reach) {
    AxisRange range;
    int lo = static_cast<int>(std::floor((x - reach - domain.min[a]) / cell_size[a]));
    int hi = static_cast<int>(std::floor((x + reach - domain.min[a]) / cell_size[a]));
    if (!domain.periodic[a]) {  // an element far outside scans the edge cell it is clamped into
      lo = std::clamp(lo, 0, cells[a] - 1);
      hi = std::clamp(hi, 0, cells[a] - 1);
    }
    // At most 2 x 4 + 2 cells: a cell is at least a quarter of the cutoff wide.
    hi = std::min(hi, lo + static_cast<int>(range.cell.size()) - 1);
    for (int k = lo; k <= hi; ++k) {
      const int wrapped_k = ((k % cells[a]) + cells[a]) % cells[a];
      range.cell[range.count] = wrapped_k;
      range.image[range.count] = static_cast<std::int8_t>((k - wrapped_k) / cells[a]);
      ++range.count;
    }
    return range;
  };

  // Each pair is found by its larger member (the higher index among equals), which then only
  // searches 2 r_i + skin around itself: a small pebble no longer scans for the largest one.
  // Each thread scans a contiguous block of i in order; the blocks are concatenated in thread
  // order and sorted stably by first member, so the list does not depend on the thread count.
  // Small systems stay on one thread: a parallel region costs more than it saves there.
  const int threads = n > 4096 ? omp_get_max_threads() : 1;
  std::vector<std::vector<Index>> block_first(threads), block_second(threads);
  std::vector<std::vector<Image>> block_image(threads);
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num();
    const int nt = omp_get_num_threads();
    const Index begin = static_cast<Index>(static_cast<long long>(n) * t / nt);
    const Index end = static_cast<Index>(static_cast<long long>(n) * (t + 1) / nt);
    auto& out_first = block_first[t];
    auto& out_second = block_second[t];
    auto& out_image = block_image[t];
    for (Index i = begin; i < end; ++i) {
      const Vec3 xi = wrapped[i];
      const double ri = elements.radius[i];
      const Index body_i = elements.body[i];
      const double search = 2.0 * ri + skin;
      const AxisRange rx = axis_range(0, xi[0], search);
      const AxisRange ry = axis_range(1, xi[1], search);
      const AxisRange rz = axis_range(2, xi[2], search);
      for (int iz = 0; iz < rz.count; ++iz) {
        for (int iy = 0; iy < ry.count; ++iy) {
          for (int ix = 0; ix < rx.count; ++ix) {
            const int c = (rz.cell[iz] * cells[1] + ry.cell[iy]) * cells[0] + rx.cell[ix];
            const Vec3 shift = image_shift({rx.image[ix], ry.image[iy], rz.image[iz]}, length);
            for (Index m = cell_start[c]; m < cell_start[c + 1]; ++m) {
              const double rj = member_radius[m];
              const Index j = cell_members[m];
              if (rj > ri || (rj == ri && j <= i) || member_body[m] == body_i) continue;
              const Vec3 d = member_position[m] + shift - xi;
              const double reach = ri + rj + skin;
              if (d.squaredNorm() >= reach * reach) continue;
              // Express the image for the unwrapped positions the solver integrates, as the
              // image of the higher index seen from the lower one.
              const Vec3 total = d - (elements.position[j] - elements.position[i]);
              const double sign = j > i ? 1.0 : -1.0;
              Image image;
              for (int a = 0; a < 3; ++a)
                image[a] = static_cast<std::int8_t>(
                    domain.periodic[a] ? std::lround(sign * total[a] / length[a]) : 0);
              out_first.push_back(std::min(i, j));
              out_second.push_back(std::max(i, j));
              out_image.push_back(image);
            }
          }
        }
      }
    }
  }
  // Stable counting sort by first member: rows in increasing i, as the solver reads them.
  std::vector<Index> row_fill(n + 1, 0);
  for (int t = 0; t < threads; ++t)
    for (Index f : block_first[t]) ++row_fill[f + 1];
  for (Index e = 0; e < n; ++e) row_fill[e + 1] += row_fill[e];
  const Index pair_count = row_fill[n];
  list.first.resize(pair_count);
  list.second.resize(pair_count);
  list.image.resize(pair_count);
  for (int t = 0; t < threads; ++t) {
    for (std::size_t k = 0; k < block_first[t].size(); ++k) {
      const Index slot = row_fill[block_first[t][k]]++;
      list.first[slot] = block_first[t][k];
      list.second[slot] = block_second[t][k];
      list.image[slot] = block_image[t][k];
    }
  }
  finish_csr(list, n);
  return list;
}

PairList brute_force_pair_list(const Elements& elements, const Domain& domain, double skin) {
  const Index n = elements.size();
  const Vec3 length = domain.length();
  PairList list;
  for (Index i = 0; i < n; ++i) {
    for (Index j = i + 1; j < n; ++j) {
      if (elements.body[i] == elements.body[j]) continue;
      Vec3 d = elements.position[j] - elements.position[i];
      Image image{0, 0, 0};
      for (int a = 0; a < 3; ++a) {
        if (!domain.periodic[a]) continue;
        image[a] = static_cast<std::int8_t>(-std::lround(d[a] / length[a]));
      }
      d += image_shift(image, length);
      const double reach = elements.radius[i] + elements.radius[j] + skin;
      if (d.squaredNorm() >= reach * reach) continue;
      list.first.push_back(i);
      list.second.push_back(j);
      list.image.push_back(image);
    }
  }
  finish_csr(list, n);
  return list;
}

}  // namespace mfdem::dem
