#pragma once
// Procedural ballast-like stones: angular convex polyhedra of controlled elongation and flatness.
//
// A stone is the convex hull of `vertices` seeded random points on an ellipsoid with axes
// proportional to (L/I, 1, S/I): few points give few, large facets and sharp edges, as crushed
// rock has. The hull is then stretched along its own principal axes until its dimensions along
// them (see ShapeIndices) match the requested elongation L/I and flatness S/I, with I = 1: the
// stone's size (its intermediate dimension, what a sieve measures) is the unit of length.
#include <cstdint>
#include <string>

#include "fidelity/triangle_mesh.hpp"

namespace mfdem::fidelity {

struct StoneSpec {
  std::string name;
  std::uint32_t seed = 1;   // GSL mt19937 seed: the same seed gives the same stone (0 acts as
                            // 4357, GSL's default seed)
  double elongation = 1.5;  // L/I, >= 1
  double flatness = 0.7;    // S/I, in (0, 1]
  int vertices = 16;        // random points on the ellipsoid, >= 8
};

// Throws std::invalid_argument naming the stone and the value when the spec is out of range.
void check_stone_spec(const StoneSpec& spec);

// The stone's surface, centroid at the origin, I = 1; elongation and flatness match the spec to
// within 1e-6 relative.
TriangleMesh generate_stone(const StoneSpec& spec);

}  // namespace mfdem::fidelity
