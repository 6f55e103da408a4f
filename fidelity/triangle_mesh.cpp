#include "fidelity/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "fidelity/shape_error.hpp"

namespace mfdem::fidelity {

namespace {

Vec3 vertex_mean(const TriangleMesh& mesh) {
  Vec3 mean = Vec3::Zero();
  for (const auto& v : mesh.vertices) mean += v;
  return mesh.vertices.empty() ? mean : Vec3(mean / static_cast<double>(mesh.vertices.size()));
}

// Moments about `reference`.
Moments moments_about(const TriangleMesh& mesh, const Vec3& reference) {
  Moments m;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]] - reference;
    const Vec3 b = mesh.vertices[t[1]] - reference;
    const Vec3 c = mesh.vertices[t[2]] - reference;
    const double volume = a.dot(b.cross(c)) / 6.0;
    const Vec3 s = a + b + c;
    m.volume += volume;
    m.first += volume * s / 4.0;
    m.second += volume / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  return m;
}

}  // namespace

Moments mesh_moments(const TriangleMesh& mesh) {
  const Vec3 reference = vertex_mean(mesh);
  return moments_about(mesh, reference).translated(reference);
}

MassProperties mesh_mass_properties(const TriangleMesh& mesh) {
  const Vec3 reference = vertex_mean(mesh);
  MassProperties p = mass_properties(moments_about(mesh, reference));
  p.centroid += reference;
  return p;
}

namespace {

std::string point_text(const Vec3& p) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", p.x(), p.y(), p.z()); }

}  // namespace

void check_closed(const TriangleMesh& mesh, std::string_view source) {
  auto fail = [&](const std::string& problem) { throw ShapeError(fmt::format("{}: {}", source, problem)); };
  if (mesh.triangles.empty()) fail("the surface has no triangles");
  const int n = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int corner : tri)
      if (corner < 0 || corner >= n) fail(fmt::format("triangle {} refers to vertex {}, but there are {}", t + 1, corner, n));
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      fail(fmt::format("triangle {} is degenerate: two of its corners are the same point {}", t + 1,
                       point_text(mesh.vertices[tri[0] == tri[1] || tri[0] == tri[2] ? tri[0] : tri[1]])));
  }
  // Directed edge -> triangles using it; a closed, consistently oriented surface uses every
  // directed edge once and its reverse once.
  std::map<std::pair<int, int>, std::vector<std::size_t>> directed;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) directed[{tri[k], tri[(k + 1) % 3]}].push_back(t);
  }
  long long open_edges = 0, overshared = 0, misoriented = 0;
  std::string first_open, first_overshared, first_misoriented;
  for (const auto& [edge, users] : directed) {
    const auto [a, b] = edge;
    const auto reverse = directed.find({b, a});
    const std::size_t forward_count = users.size();
    const std::size_t reverse_count = reverse == directed.end() ? 0 : reverse->second.size();
    const std::size_t total = forward_count + reverse_count;
    if (a > b && reverse != directed.end()) continue;  // the pair was seen from (b, a)
    const std::string where = fmt::format("the edge from {} to {}", point_text(mesh.vertices[a]), point_text(mesh.vertices[b]));
    if (total == 1) {
      if (open_edges++ == 0) first_open = fmt::format("{} belongs to only one triangle (triangle {})", where, users[0] + 1);
    } else if (total > 2) {
      if (overshared++ == 0) first_overshared = fmt::format("{} is shared by {} triangles", where, total);
    } else if (forward_count == 2) {
      if (misoriented++ == 0)
        first_misoriented = fmt::format("triangles {} and {} both run along {} in the same direction", users[0] + 1,
                                        users[1] + 1, where);
    }
  }
  if (open_edges > 0)
    fail(fmt::format("the surface is open (not watertight): {}; every edge of a closed surface must be shared by "
                     "exactly two triangles ({} open edge{} in all)",
                     first_open, open_edges, open_edges == 1 ? "" : "s"));
  if (overshared > 0)
    fail(fmt::format("the surface is not a closed solid (non-manifold): {}; every edge must be shared by exactly two "
                     "triangles ({} such edge{} in all)",
                     first_overshared, overshared, overshared == 1 ? "" : "s"));
  if (misoriented > 0)
    fail(fmt::format("the triangles are not consistently oriented: {}; neighbours must run along a shared edge in "
                     "opposite directions ({} such edge{} in all)",
                     first_misoriented, misoriented, misoriented == 1 ? "" : "s"));
}

double winding_number(const TriangleMesh& mesh, const Vec3& p) {
  double solid_angle = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]] - p;
    const Vec3 b = mesh.vertices[t[1]] - p;
    const Vec3 c = mesh.vertices[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    solid_angle += 2.0 * std::atan2(numerator, denominator);
  }
  return solid_angle / (4.0 * std::numbers::pi);
}

bool inside(const TriangleMesh& mesh, const Vec3& p) { return winding_number(mesh, p) > 0.5; }

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi regions of the corners, then of the edges, else the face (barycentric coordinates).
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

double distance_to_surface(const TriangleMesh& mesh, const Vec3& p) {
  double nearest2 = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    const Vec3 q = closest_point_on_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    nearest2 = std::min(nearest2, (q - p).squaredNorm());
  }
  return std::sqrt(nearest2);
}

ShapeIndices shape_indices(const TriangleMesh& mesh) {
  const MassProperties solid = mesh_mass_properties(mesh);
  const Mat3 axes = principal_axes(solid.inertia).axes;
  std::array<double, 3> extent{};
  for (int k = 0; k < 3; ++k) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& v : mesh.vertices) {
      const double s = (v - solid.centroid).dot(axes.col(k));
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
    extent[k] = hi - lo;
  }
  std::sort(extent.begin(), extent.end());
  return ShapeIndices{extent[2], extent[1], extent[0]};
}

TriangleMesh transformed(const TriangleMesh& mesh, const Vec3& origin, const Mat3& rotation, double scale) {
  TriangleMesh result = mesh;
  for (auto& v : result.vertices) v = scale * (rotation * (v - origin));
  return result;
}

}  // namespace mfdem::fidelity
