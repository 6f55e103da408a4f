// Generated ballast-like stones: closed convex polyhedra of the requested elongation and flatness,
// the same for the same seed.
#include <catch2/catch.hpp>

#include "fidelity/stone_generator.hpp"

using namespace mfdem::fidelity;

TEST_CASE("generated stones have the requested elongation L/I and flatness S/I", "[fidelity][shapes]") {
  // The stretch iteration stops at 1e-9; the dimensions are measured afresh here, so 1e-6 covers
  // rounding with room to spare.
  for (const StoneSpec& spec : {StoneSpec{"a", 1, 1.2, 0.8, 12}, StoneSpec{"b", 2, 1.5, 0.6, 16},
                                StoneSpec{"c", 3, 2.0, 0.5, 24}, StoneSpec{"d", 4, 1.0, 1.0, 40}}) {
    CAPTURE(spec.name);
    const TriangleMesh stone = generate_stone(spec);
    REQUIRE_NOTHROW(check_closed(stone, spec.name));
    const ShapeIndices shape = shape_indices(stone);
    CHECK(shape.intermediate == Approx(1.0).epsilon(1e-6));
    CHECK(shape.elongation() == Approx(spec.elongation).epsilon(1e-6));
    CHECK(shape.flatness() == Approx(spec.flatness).epsilon(1e-6));
    CHECK(mesh_mass_properties(stone).centroid.norm() < 1e-12);
    // Convex: every vertex lies on or behind every face plane.
    for (const auto& t : stone.triangles) {
      const Vec3& a = stone.vertices[t[0]];
      const Vec3 n = (stone.vertices[t[1]] - a).cross(stone.vertices[t[2]] - a).normalized();
      for (const auto& v : stone.vertices) CHECK((v - a).dot(n) < 1e-12);
    }
  }
}

TEST_CASE("the same seed gives the same stone, another seed another", "[fidelity][shapes]") {
  const StoneSpec spec{"s", 42, 1.4, 0.7, 16};
  const TriangleMesh a = generate_stone(spec);
  const TriangleMesh b = generate_stone(spec);
  REQUIRE(a.vertices.size() == b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i) CHECK(a.vertices[i] == b.vertices[i]);
  StoneSpec other = spec;
  other.seed = 43;
  CHECK(mesh_mass_properties(generate_stone(other)).volume != mesh_mass_properties(a).volume);
}

TEST_CASE("a stone spec out of range is refused with the value", "[fidelity][shapes]") {
  CHECK_THROWS_WITH(generate_stone({"x", 1, 0.9, 0.5, 16}), "stone 'x': elongation L/I must be >= 1 (got 0.9)");
  CHECK_THROWS_WITH(generate_stone({"x", 1, 1.5, 0.0, 16}), "stone 'x': flatness S/I must be in (0, 1] (got 0)");
  CHECK_THROWS_WITH(generate_stone({"x", 1, 1.5, 0.5, 5}), "stone 'x': vertices must be between 8 and 1000 (got 5)");
}
