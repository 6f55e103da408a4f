// STL surfaces: ASCII and binary round trips, and the rejection of open meshes and of garbage
// with a message naming the file and the problem.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>

#include "fidelity/shape_error.hpp"
#include "fidelity/stl.hpp"
#include "fidelity/stone_generator.hpp"
#include "tests/fidelity/mesh_shapes.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem::fidelity;
using mfdem::test::TempDir;
using mfdem::test::unit_cube;
using Catch::Contains;
using Catch::StartsWith;

namespace {

TriangleMesh stone() { return generate_stone({"stl_stone", 7, 1.6, 0.6, 16}); }

// Same triangles over the same points, vertex numbering aside; `tolerance` on coordinates.
void require_same_surface(const TriangleMesh& a, const TriangleMesh& b, double tolerance) {
  REQUIRE(a.triangles.size() == b.triangles.size());
  REQUIRE(a.vertices.size() == b.vertices.size());
  for (std::size_t t = 0; t < a.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      CHECK((a.vertices[a.triangles[t][k]] - b.vertices[b.triangles[t][k]]).norm() <= tolerance);
}

}  // namespace

TEST_CASE("ASCII STL round trip is exact", "[fidelity][stl]") {
  const TempDir dir;
  const TriangleMesh original = stone();
  write_stl(original, dir.path() / "stone.stl", StlEncoding::ascii, "stone");
  const TriangleMesh read = read_stl(dir.path() / "stone.stl");
  require_same_surface(original, read, 0.0);  // 17 significant digits read back exactly
  CHECK(mesh_mass_properties(read).volume == mesh_mass_properties(original).volume);
}

TEST_CASE("binary STL round trip keeps single precision", "[fidelity][stl]") {
  const TempDir dir;
  const TriangleMesh original = stone();
  write_stl(original, dir.path() / "stone.stl", StlEncoding::binary);
  CHECK(std::filesystem::file_size(dir.path() / "stone.stl") == 84 + 50 * original.triangles.size());
  const TriangleMesh read = read_stl(dir.path() / "stone.stl");
  // Coordinates of order 1 as 32-bit floats: rounding error below 2^-24 ~ 6e-8.
  require_same_surface(original, read, 1e-7);
  CHECK(mesh_mass_properties(read).volume == Approx(mesh_mass_properties(original).volume).epsilon(1e-6));
  // A binary file whose header starts with "solid" is still read as binary.
  std::string bytes = format_stl(original, StlEncoding::binary);
  std::memcpy(bytes.data(), "solid trap", 10);
  CHECK(parse_stl(bytes, "trap.stl").triangles.size() == original.triangles.size());
}

TEST_CASE("an STL whose triangles face inwards is turned outwards", "[fidelity][stl]") {
  TriangleMesh inverted = unit_cube();
  for (auto& t : inverted.triangles) std::swap(t[1], t[2]);
  const TriangleMesh read = parse_stl(format_stl(inverted, StlEncoding::ascii), "inverted.stl");
  CHECK(mesh_mass_properties(read).volume == Approx(1.0).epsilon(1e-14));
}

TEST_CASE("an open STL is rejected, naming the file and the open edge", "[fidelity][stl]") {
  const TempDir dir;
  TriangleMesh open = unit_cube();
  open.triangles.erase(open.triangles.begin() + 3);
  for (auto encoding : {StlEncoding::ascii, StlEncoding::binary}) {
    const auto file = dir.write("open.stl", format_stl(open, encoding));
    CHECK_THROWS_AS(read_stl(file), ShapeError);
    CHECK_THROWS_WITH(read_stl(file), StartsWith(file.string() + ": the surface is open (not watertight): the edge from") &&
                                          Contains("every edge of a closed surface must be shared by exactly two triangles"));
  }
}

TEST_CASE("garbage, truncated and empty files are not STL", "[fidelity][stl]") {
  const TempDir dir;
  std::string noise(1000, '\0');
  for (std::size_t i = 0; i < noise.size(); ++i) noise[i] = static_cast<char>((i * 7919 + 13) % 251);
  CHECK_THROWS_WITH(read_stl(dir.write("noise.stl", noise)),
                    Contains("noise.stl: is not an STL file: it does not start with 'solid' (ASCII STL), and its size, "
                             "1000 bytes, does not match"));
  CHECK_THROWS_WITH(read_stl(dir.write("short.stl", "hello")),
                    Contains("short.stl: is not an STL file") && Contains("shorter (5 bytes) than the 84-byte header"));
  CHECK_THROWS_WITH(read_stl(dir.write("empty.stl", "")), Contains("empty.stl: is empty"));
  std::string binary = format_stl(unit_cube(), StlEncoding::binary);
  binary.resize(binary.size() - 20);
  CHECK_THROWS_WITH(read_stl(dir.write("cut.stl", binary)), Contains("does not match the 12 triangles its binary header announces"));
  CHECK_THROWS_WITH(read_stl(dir.path() / "missing.stl"), Contains("missing.stl: cannot be opened"));
}

TEST_CASE("ASCII STL syntax errors name the line", "[fidelity][stl]") {
  const std::string text =
      "solid s\n"
      "facet normal 0 0 1\n"
      "  outer loop\n"
      "    vertex 0 0 0\n"
      "    vertex 1 0 zero\n";
  CHECK_THROWS_WITH(parse_stl(text, "bad.stl"),
                    Catch::Equals("bad.stl:5: expected a vertex z coordinate (a number), found 'zero' (ASCII STL)"));
  CHECK_THROWS_WITH(parse_stl("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", "cut.stl"),
                    Contains("cut.stl:4: the file ends where 'vertex' was expected"));
  CHECK_THROWS_WITH(parse_stl("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 inf\n", "inf.stl"),
                    Contains("coordinates must be finite"));
}
