#include "dem/neighbor_list.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mfdem::dem {
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

double max_radius(const Elements& elements) {
  double r = 0.0;
  for (double ri : elements.radius) r = std::max(r, ri);
  return r;
}

}  // namespace

PairList build_pair_list(const Elements& elements, const Domain& domain, double skin) {
  const Index n = elements.size();
  PairList list;
  if (n == 0) {
    finish_csr(list, 0);
    return list;
  }
  const double cutoff = 2.0 * max_radius(elements) + skin;
  const Vec3 length = domain.length();
  std::array<int, 3> cells{};
  for (int a = 0; a < 3; ++a) {
    cells[a] = std::max(1, static_cast<int>(std::floor(length[a] / cutoff)));
    if (domain.periodic[a] && cells[a] < 3)
      throw std::invalid_argument(
          "periodic box length along axis " + std::string(1, "xyz"[a]) + " (" +
          std::to_string(length[a]) + " m) must be at least 3 x (largest diameter + skin) = " +
          std::to_string(3.0 * cutoff) + " m");
  }
  const Vec3 cell_size(length[0] / cells[0], length[1] / cells[1], length[2] / cells[2]);

  // Bin wrapped positions; clamp along walled axes (clamping keeps near pairs adjacent).
  std::vector<Vec3> wrapped(n);
  std::vector<int> cell_of(n);
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
  for (Index m = 0; m < n; ++m) {
    const Index e = cell_members[m];
    member_position[m] = wrapped[e];
    member_radius[m] = elements.radius[e];
    member_body[m] = elements.body[e];
  }

  // Each thread scans a contiguous block of i in order; concatenating the blocks in thread
  // order gives the same list whatever the thread count.
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
    // A neighbour cell reached across a periodic face holds images one box length away. With at
    // least three cells along such an axis each neighbour cell is a distinct cell, and for a pair
    // within the cutoff (at most a third of the box) this image is the nearest one.
    auto neighbour = [&](int c, int d, int a, std::int8_t& image) {
      image = 0;
      const int k = c + d;
      if (k >= 0 && k < cells[a]) return k;
      if (!domain.periodic[a]) return -1;
      image = k < 0 ? -1 : 1;
      return k < 0 ? k + cells[a] : k - cells[a];
    };
    for (Index i = begin; i < end; ++i) {
      const int ci = cell_of[i];
      const int cx = ci % cells[0], cy = (ci / cells[0]) % cells[1], cz = ci / (cells[0] * cells[1]);
      const Vec3 xi = wrapped[i];
      const double ri = elements.radius[i];
      const Index body_i = elements.body[i];
      Image cell_image;
      for (int dz = -1; dz <= 1; ++dz) {
        const int z = neighbour(cz, dz, 2, cell_image[2]);
        if (z < 0) continue;
        for (int dy = -1; dy <= 1; ++dy) {
          const int y = neighbour(cy, dy, 1, cell_image[1]);
          if (y < 0) continue;
          for (int dx = -1; dx <= 1; ++dx) {
            const int x = neighbour(cx, dx, 0, cell_image[0]);
            if (x < 0) continue;
            const int c = (z * cells[1] + y) * cells[0] + x;
            const Vec3 shift = image_shift(cell_image, length);
            for (Index m = cell_start[c]; m < cell_start[c + 1]; ++m) {
              const Index j = cell_members[m];
              if (j <= i || member_body[m] == body_i) continue;
              const Vec3 d = member_position[m] + shift - xi;
              const double reach = ri + member_radius[m] + skin;
              if (d.squaredNorm() >= reach * reach) continue;
              // Express the image for the unwrapped positions the solver integrates.
              const Vec3 total = d - (elements.position[j] - elements.position[i]);
              Image image;
              for (int a = 0; a < 3; ++a)
                image[a] = static_cast<std::int8_t>(
                    domain.periodic[a] ? std::lround(total[a] / length[a]) : 0);
              out_first.push_back(i);
              out_second.push_back(j);
              out_image.push_back(image);
            }
          }
        }
      }
    }
  }
  for (int t = 0; t < threads; ++t) {
    list.first.insert(list.first.end(), block_first[t].begin(), block_first[t].end());
    list.second.insert(list.second.end(), block_second[t].begin(), block_second[t].end());
    list.image.insert(list.image.end(), block_image[t].begin(), block_image[t].end());
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
