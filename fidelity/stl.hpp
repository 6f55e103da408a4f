#pragma once
// STL surfaces (stereolithography: the format 3D scanners and CAD export), ASCII and binary.
//
// read_stl detects the encoding: binary when the size is exactly 84 + 50 n bytes for the n
// triangles its header announces (binary files may also begin with "solid"), else ASCII
// ("solid name / facet normal ... / outer loop / vertex x y z (3x) / endloop / endfacet ... /
// endsolid"). STL stores each triangle's corners separately; corners with identical coordinates
// are merged into one vertex. Facet normals are ignored; orientation comes from the corner order.
// The surface must be closed (check_closed): an open or non-manifold mesh, a degenerate triangle,
// a number that is not finite and any syntax error are rejected with a ShapeError naming the file
// (and the line, for ASCII). A closed surface whose triangles all face inwards is turned outwards.
#include <filesystem>
#include <string>
#include <string_view>

#include "fidelity/triangle_mesh.hpp"

namespace mfdem::fidelity {

TriangleMesh read_stl(const std::filesystem::path& file);
// The same checks on bytes already in memory; `source` stands for the file in messages.
TriangleMesh parse_stl(std::string_view bytes, std::string_view source);

enum class StlEncoding { ascii, binary };

// Writes every triangle with its unit normal; ASCII numbers round-trip exactly ({:.17g}), binary
// ones are 32-bit floats as the format demands.
void write_stl(const TriangleMesh& mesh, const std::filesystem::path& file, StlEncoding encoding,
               std::string_view solid_name = "mfdem");
std::string format_stl(const TriangleMesh& mesh, StlEncoding encoding, std::string_view solid_name = "mfdem");

}  // namespace mfdem::fidelity
