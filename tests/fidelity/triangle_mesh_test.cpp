// Volume and inertia of triangle meshes by the divergence theorem, closedness checks, inside and
// distance queries, convex hulls. The mass properties are exact up to rounding: 1e-13.
#include <catch2/catch.hpp>

#include <cmath>

#include "fidelity/convex_hull.hpp"
#include "fidelity/shape_error.hpp"
#include "fidelity/triangle_mesh.hpp"
#include "tests/fidelity/mesh_shapes.hpp"

using namespace mfdem::fidelity;
using mfdem::test::right_tetrahedron;
using mfdem::test::unit_cube;

namespace {
constexpr double exact = 1e-13;
}

TEST_CASE("unit cube: V = 1, centroid (1/2, 1/2, 1/2), I = 1/6 on the diagonal", "[fidelity][mesh]") {
  const MassProperties p = mass_properties(mesh_moments(unit_cube()));
  CHECK(p.volume == Approx(1.0).epsilon(exact));
  CHECK((p.centroid - Vec3::Constant(0.5)).norm() < exact);
  // I_xx = integral of (y^2 + z^2) about the centre = 2 x 1/12 = 1/6; products of inertia vanish.
  CHECK((p.inertia - Mat3::Identity() / 6.0).norm() < exact);
}

TEST_CASE("right tetrahedron: V = 1/6, centroid 1/4, I_xx = 1/80, I_xy = 1/480", "[fidelity][mesh]") {
  // About the origin: integral of x^2 = 1/60 and of x y = 1/120 over the tetrahedron. About the
  // centroid (1/4 each): x^2 -> 1/60 - V/16 = 1/160, x y -> 1/120 - V/16 = -1/480. Hence
  // I_xx = 2/160 = 1/80 and I_xy = -(-1/480) = 1/480.
  const MassProperties p = mass_properties(mesh_moments(right_tetrahedron()));
  CHECK(p.volume == Approx(1.0 / 6.0).epsilon(exact));
  CHECK((p.centroid - Vec3::Constant(0.25)).norm() < exact);
  Mat3 expected = Mat3::Constant(1.0 / 480.0);
  expected.diagonal().setConstant(1.0 / 80.0);
  CHECK((p.inertia - expected).norm() < exact);
}

TEST_CASE("a moved and turned cube keeps its volume and its inertia turns with it", "[fidelity][mesh]") {
  const Mat3 turn = Eigen::AngleAxisd(0.9, Vec3(1, -1, 2).normalized()).toRotationMatrix();
  TriangleMesh cube = unit_cube();
  for (auto& v : cube.vertices) v = turn * (3.0 * v) + Vec3(100, -50, 7);  // side 3, far from the origin
  const MassProperties p = mesh_mass_properties(cube);
  CHECK(p.volume == Approx(27.0).epsilon(1e-12));
  CHECK((p.centroid - (turn * Vec3::Constant(1.5) + Vec3(100, -50, 7))).norm() < 1e-10);
  // A cube's inertia is isotropic: m s^2 / 6 = 27 x 9 / 6 in every direction.
  CHECK((p.inertia - Mat3::Identity() * 27.0 * 9.0 / 6.0).norm() / (27.0 * 9.0 / 6.0) < 1e-12);
}

TEST_CASE("winding number and distance to the surface of the unit cube", "[fidelity][mesh]") {
  const TriangleMesh cube = unit_cube();
  CHECK(winding_number(cube, Vec3(0.3, 0.6, 0.5)) == Approx(1.0).margin(1e-12));
  CHECK(winding_number(cube, Vec3(1.3, 0.6, 0.5)) == Approx(0.0).margin(1e-12));
  CHECK(inside(cube, Vec3(0.1, 0.9, 0.2)));
  CHECK_FALSE(inside(cube, Vec3(-0.1, 0.9, 0.2)));
  CHECK(distance_to_surface(cube, Vec3(0.3, 0.6, 0.5)) == Approx(0.3).epsilon(exact));
  CHECK(distance_to_surface(cube, Vec3(2, 2, 2)) == Approx(std::sqrt(3.0)).epsilon(exact));  // to the corner
  CHECK(distance_to_surface(cube, Vec3(0.5, 2, 3)) == Approx(std::sqrt(5.0)).epsilon(exact));  // to an edge
}

TEST_CASE("check_closed names the open edge, the shared edge and the flipped triangle", "[fidelity][mesh]") {
  CHECK_NOTHROW(check_closed(unit_cube(), "cube"));
  TriangleMesh open = unit_cube();
  open.triangles.pop_back();
  CHECK_THROWS_AS(check_closed(open, "open.stl"), ShapeError);
  CHECK_THROWS_WITH(check_closed(open, "open.stl"),
                    Catch::StartsWith("open.stl: the surface is open (not watertight): the edge from") &&
                        Catch::Contains("belongs to only one triangle") && Catch::Contains("(3 open edges in all)"));
  TriangleMesh flipped = unit_cube();
  std::swap(flipped.triangles[5][1], flipped.triangles[5][2]);
  CHECK_THROWS_WITH(check_closed(flipped, "flipped"), Catch::Contains("not consistently oriented"));
  TriangleMesh fin = unit_cube();
  fin.vertices.emplace_back(0.5, 0.5, 2.0);
  fin.triangles.push_back({4, 5, 8});
  fin.triangles.push_back({5, 4, 8});
  CHECK_THROWS_WITH(check_closed(fin, "fin"), Catch::Contains("non-manifold") && Catch::Contains("shared by 4 triangles"));
  TriangleMesh degenerate = unit_cube();
  degenerate.triangles[0] = {0, 0, 1};
  CHECK_THROWS_WITH(check_closed(degenerate, "d"), Catch::Contains("triangle 1 is degenerate"));
}

TEST_CASE("convex hull of a cube's corners and inner points is the cube", "[fidelity][mesh]") {
  std::vector<Vec3> points = unit_cube().vertices;
  points.emplace_back(0.5, 0.5, 0.5);
  points.emplace_back(0.2, 0.7, 0.4);
  const TriangleMesh hull = convex_hull(points);
  CHECK(hull.vertices.size() == 8);
  CHECK_NOTHROW(check_closed(hull, "hull"));
  const MassProperties p = mass_properties(mesh_moments(hull));
  CHECK(p.volume == Approx(1.0).epsilon(exact));
  CHECK((p.inertia - Mat3::Identity() / 6.0).norm() < exact);
  const std::vector<Vec3> flat{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  CHECK_THROWS_WITH(convex_hull(flat), Catch::Contains("one plane"));
}
