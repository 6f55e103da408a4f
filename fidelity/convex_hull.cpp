#include "fidelity/convex_hull.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

namespace mfdem::fidelity {

namespace {

struct Face {
  std::array<int, 3> v;
  Vec3 normal;  // outward, unit
  double offset = 0.0;  // plane: normal.x = offset
  bool alive = true;
};

Face make_face(std::span<const Vec3> p, int a, int b, int c) {
  Face f;
  f.v = {a, b, c};
  f.normal = (p[b] - p[a]).cross(p[c] - p[a]).normalized();
  f.offset = f.normal.dot(p[a]);
  return f;
}

}  // namespace

TriangleMesh convex_hull(std::span<const Vec3> points) {
  const int n = static_cast<int>(points.size());
  if (n < 4) throw std::invalid_argument("a convex hull needs at least four points");

  double scale = 0.0;
  for (const auto& p : points) scale = std::max(scale, (p - points[0]).norm());
  const double eps = 1e-12 * std::max(scale, 1e-300);

  // Initial tetrahedron from extreme points: far apart, then far from the line, then the plane.
  int i0 = 0;
  for (int i = 1; i < n; ++i)
    if (points[i].x() < points[i0].x()) i0 = i;
  int i1 = i0;
  for (int i = 0; i < n; ++i)
    if ((points[i] - points[i0]).squaredNorm() > (points[i1] - points[i0]).squaredNorm()) i1 = i;
  const Vec3 line = (points[i1] - points[i0]).normalized();
  int i2 = i0;
  double best = 0.0;
  for (int i = 0; i < n; ++i) {
    const double d = (points[i] - points[i0]).cross(line).norm();
    if (d > best) best = d, i2 = i;
  }
  if (best <= eps) throw std::invalid_argument("the points of a convex hull all lie on one line");
  const Vec3 plane = (points[i1] - points[i0]).cross(points[i2] - points[i0]).normalized();
  int i3 = i0;
  best = 0.0;
  for (int i = 0; i < n; ++i) {
    const double d = std::abs((points[i] - points[i0]).dot(plane));
    if (d > best) best = d, i3 = i;
  }
  if (best <= eps) throw std::invalid_argument("the points of a convex hull all lie in one plane");

  std::vector<Face> faces;
  const Vec3 inner = (points[i0] + points[i1] + points[i2] + points[i3]) / 4.0;
  for (const auto& [a, b, c] : {std::array{i0, i1, i2}, std::array{i0, i1, i3}, std::array{i0, i2, i3},
                                std::array{i1, i2, i3}}) {
    Face f = make_face(points, a, b, c);
    if (f.normal.dot(inner) > f.offset) f = make_face(points, a, c, b);
    faces.push_back(f);
  }

  std::vector<bool> used(n, false);
  for (int i : {i0, i1, i2, i3}) used[i] = true;
  for (int i = 0; i < n; ++i) {
    if (used[i]) continue;
    const Vec3& p = points[i];
    std::vector<std::size_t> visible;
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (faces[f].alive && faces[f].normal.dot(p) - faces[f].offset > eps) visible.push_back(f);
    if (visible.empty()) continue;  // inside or on the hull
    // Horizon: directed edges of visible faces whose reverse belongs to a face that stays.
    std::map<std::pair<int, int>, bool> edge_visible;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (!faces[f].alive) continue;
      const bool seen = std::find(visible.begin(), visible.end(), f) != visible.end();
      for (int k = 0; k < 3; ++k) edge_visible[{faces[f].v[k], faces[f].v[(k + 1) % 3]}] = seen;
    }
    std::vector<std::pair<int, int>> horizon;
    for (std::size_t f : visible)
      for (int k = 0; k < 3; ++k) {
        const int a = faces[f].v[k], b = faces[f].v[(k + 1) % 3];
        if (!edge_visible.at({b, a})) horizon.emplace_back(a, b);
      }
    for (std::size_t f : visible) faces[f].alive = false;
    for (const auto& [a, b] : horizon) faces.push_back(make_face(points, a, b, i));
    used[i] = true;
    std::erase_if(faces, [](const Face& f) { return !f.alive; });
  }

  // Keep only the corners that faces use, numbered in input order.
  TriangleMesh hull;
  std::vector<int> index(n, -1);
  for (const auto& f : faces)
    for (int v : f.v) index[v] = 0;
  for (int i = 0; i < n; ++i)
    if (index[i] == 0) {
      index[i] = static_cast<int>(hull.vertices.size());
      hull.vertices.push_back(points[i]);
    }
  for (const auto& f : faces) hull.triangles.push_back({index[f.v[0]], index[f.v[1]], index[f.v[2]]});
  return hull;
}

}  // namespace mfdem::fidelity
