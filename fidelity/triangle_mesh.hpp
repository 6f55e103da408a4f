#pragma once
// A closed triangulated surface (a stone's outline) and what follows from it exactly: volume,
// centroid and inertia by the divergence theorem, inside/outside, distance to the surface, and
// the shape indices of the stone.
#include <array>
#include <string_view>
#include <vector>

#include "fidelity/mass_properties.hpp"

namespace mfdem::fidelity {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside
};

// Moments of the enclosed solid (unit density), exact for a closed, outward-oriented mesh: each
// triangle (a, b, c) spans a tetrahedron with a reference point o; with a, b, c taken relative to
// o its signed volume is a.(b x c)/6, its first moment V (a + b + c)/4 and its second moment
// V/20 (a a^T + b b^T + c c^T + s s^T), s = a + b + c (Tonon 2004, J. Math. Stat. 1(1), 8-11;
// the reference point cancels for a closed surface and is taken at the vertex mean for accuracy).
Moments mesh_moments(const TriangleMesh& mesh);
// Volume, centroid and inertia about the centroid, computed about the vertex mean, so that a
// mesh far from the origin loses no accuracy.
MassProperties mesh_mass_properties(const TriangleMesh& mesh);

// Checks that the mesh is a closed, consistently oriented surface: indices in range, no triangle
// with a repeated corner, every edge shared by exactly two triangles that run along it in opposite
// directions. Throws ShapeError "<source>: <problem>" naming the first offending edge or triangle.
void check_closed(const TriangleMesh& mesh, std::string_view source);

// Generalised winding number of a closed mesh around p (sum of solid angles / 4 pi, Van Oosterom &
// Strackee 1983): 1 inside, 0 outside, robust to small defects.
double winding_number(const TriangleMesh& mesh, const Vec3& p);
bool inside(const TriangleMesh& mesh, const Vec3& p);

// Closest point of triangle (a, b, c) to p, and the distance from p to the surface.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
double distance_to_surface(const TriangleMesh& mesh, const Vec3& p);

// Dimensions of a stone along the principal axes of its solid, longest first: L >= I >= S, with
// elongation L/I >= 1 and flatness S/I <= 1. The intermediate dimension I is what a square sieve
// measures, and is taken as the stone's size.
struct ShapeIndices {
  double length = 0.0;        // L
  double intermediate = 0.0;  // I
  double thickness = 0.0;     // S
  double elongation() const { return length / intermediate; }
  double flatness() const { return thickness / intermediate; }
};

ShapeIndices shape_indices(const TriangleMesh& mesh);

// Every vertex mapped through x -> rotation (x - origin) * scale.
TriangleMesh transformed(const TriangleMesh& mesh, const Vec3& origin, const Mat3& rotation, double scale);

}  // namespace mfdem::fidelity
