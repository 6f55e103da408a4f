#pragma once
// Convex hull of a point set in 3D, as a closed triangle mesh oriented outwards.
//
// Incremental (beneath-beyond) construction: start from a non-degenerate tetrahedron, then add
// each point outside the current hull by removing the faces it sees and joining it to the horizon.
// O(n^2) for n points: meant for the tens of vertices of a generated stone, not for scans.
#include <span>

#include "fidelity/triangle_mesh.hpp"

namespace mfdem::fidelity {

// Only points that are corners of the hull appear in the result. Throws std::invalid_argument for
// fewer than four points or points that all lie in one plane.
TriangleMesh convex_hull(std::span<const Vec3> points);

}  // namespace mfdem::fidelity
