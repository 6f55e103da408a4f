#pragma once
// Filling a closed surface with overlapping pebbles (bubble packing), for clump templates.
//
// The interior is sampled on a grid of cubic cells; at each cell centre inside the surface the
// distance to the surface is computed exactly (closest point on the triangles). A pebble centred
// at a sample has that distance as radius: the largest sphere there that stays inside the surface.
// Pebbles are placed one at a time, each at the sample chosen by the rule below, until the
// resolution knob is reached: `pebbles` placed, or no admissible sample left whose sphere would
// be at least `min_radius` and add uncovered volume.
//
// Rules:
// - largest_new_volume (default): the sphere that covers the most interior samples not yet
//   covered. This is greedy maximum coverage, which minimises the volume error step by step;
//   coverage is submodular (a sphere's gain only shrinks as others are placed), so the lazy
//   evaluation used here returns exactly the greedy choice (Minoux 1978).
// - farthest_point: the sample farthest from both the surface and the pebbles placed so far
//   (maximises min(distance to surface, distance outside the existing pebbles)); cheaper, and the
//   classic bubble-pack heuristic, but it leaves more volume uncovered for few pebbles.
// Each new pebble adds uncovered volume, so the clump's volume grows with every pebble and the
// sequence for n pebbles starts with the one for fewer: the volume error falls with resolution.
#include <vector>

#include "fidelity/pebble.hpp"
#include "fidelity/triangle_mesh.hpp"

namespace mfdem::fidelity {

enum class BubblePackRule { largest_new_volume, farthest_point };

struct BubblePackOptions {
  int pebbles = 6;          // at most this many pebbles
  double min_radius = 0.0;  // no pebble smaller than this (mesh units); 0: no limit
  int grid_cells = 40;      // cells along the longest side of the surface's bounding box
  BubblePackRule rule = BubblePackRule::largest_new_volume;
};

// Pebbles in the mesh's frame, in the order placed (largest gain first). The mesh must be closed
// (check_closed). Throws std::invalid_argument for options out of range.
std::vector<Pebble> bubble_pack(const TriangleMesh& surface, const BubblePackOptions& options = {});

}  // namespace mfdem::fidelity
