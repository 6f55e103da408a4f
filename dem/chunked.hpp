#pragma once
// Deterministic parallel loops.
//
// Work is cut into fixed-size chunks that do not depend on the thread count; per-chunk partial
// sums are added in chunk order afterwards. So a sum over 20,000 spheres is bitwise the same on
// 1, 2 or 64 threads, which plain OpenMP reductions do not guarantee.
#include <algorithm>

#include "dem/types.hpp"

namespace mfdem::dem {

inline constexpr Index kChunkSize = 256;

inline Index chunk_count(Index n) { return (n + kChunkSize - 1) / kChunkSize; }
inline Index chunk_begin(Index chunk) { return chunk * kChunkSize; }
inline Index chunk_end(Index chunk, Index n) { return std::min(n, (chunk + 1) * kChunkSize); }

}  // namespace mfdem::dem
