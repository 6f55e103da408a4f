#include "fidelity/stl.hpp"

#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "fidelity/shape_error.hpp"

namespace mfdem::fidelity {

namespace {

constexpr std::size_t binary_header_bytes = 80;
constexpr std::size_t binary_count_bytes = 4;
constexpr std::size_t binary_triangle_bytes = 50;  // normal, 3 corners (12 floats) + 2 attribute bytes

static_assert(std::endian::native == std::endian::little, "binary STL reading assumes a little-endian machine");

// Corners with identical coordinates become one vertex.
class Welder {
 public:
  int index(const Vec3& p) {
    const auto [it, inserted] = ids_.try_emplace(std::make_tuple(p.x(), p.y(), p.z()), static_cast<int>(mesh.vertices.size()));
    if (inserted) mesh.vertices.push_back(p);
    return it->second;
  }
  TriangleMesh mesh;

 private:
  std::map<std::tuple<double, double, double>, int> ids_;
};

TriangleMesh parse_binary(std::string_view bytes, std::string_view source, std::uint32_t count) {
  Welder welder;
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* record = bytes.data() + binary_header_bytes + binary_count_bytes + t * binary_triangle_bytes;
    std::array<float, 12> values;
    std::memcpy(values.data(), record, sizeof values);
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p(values[3 + 3 * k], values[4 + 3 * k], values[5 + 3 * k]);
      if (!p.allFinite())
        throw ShapeError(fmt::format("{}: triangle {} has a corner that is not a finite number (binary STL)", source, t + 1));
      tri[k] = welder.index(p);
    }
    welder.mesh.triangles.push_back(tri);
  }
  return std::move(welder.mesh);
}

// Whitespace-separated words with their line numbers.
class Words {
 public:
  Words(std::string_view text, std::string_view source) : text_(text), source_(source) {}

  bool done() {
    skip_space();
    return pos_ >= text_.size();
  }
  std::string_view next(std::string_view expected) {
    skip_space();
    if (pos_ >= text_.size()) fail(fmt::format("the file ends where {} was expected", expected));
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    word_line_ = line_;
    return text_.substr(start, pos_ - start);
  }
  void expect(std::string_view keyword, std::string_view context) {
    const auto word = next(fmt::format("'{}'", keyword));
    if (word != keyword) fail(fmt::format("expected '{}' {}, found '{}'", keyword, context, shorten(word)));
  }
  double number(std::string_view what) {
    const auto word = next(what);
    double value = 0.0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (error != std::errc() || end != word.data() + word.size())
      fail(fmt::format("expected {} (a number), found '{}'", what, shorten(word)));
    if (!std::isfinite(value)) fail(fmt::format("{} is '{}'; coordinates must be finite numbers", what, shorten(word)));
    return value;
  }
  void skip_rest_of_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  [[noreturn]] void fail(std::string_view problem) const {
    throw ShapeError(fmt::format("{}:{}: {} (ASCII STL)", source_, word_line_, problem));
  }

 private:
  static std::string shorten(std::string_view word) {
    std::string printable;
    for (char c : word.substr(0, 40)) printable += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
    return word.size() > 40 ? printable + "..." : printable;
  }
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  std::string_view text_;
  std::string_view source_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int word_line_ = 1;
};

TriangleMesh parse_ascii(std::string_view text, std::string_view source) {
  Words words(text, source);
  words.expect("solid", "at the start of an ASCII STL file");
  words.skip_rest_of_line();  // the solid's name
  Welder welder;
  for (;;) {
    const auto word = words.next("'facet' or 'endsolid'");
    if (word == "endsolid") break;
    if (word != "facet") words.fail(fmt::format("expected 'facet' or 'endsolid', found '{}'", word.substr(0, 40)));
    words.expect("normal", "after 'facet'");
    for (const char* axis : {"the normal's x", "the normal's y", "the normal's z"}) words.number(axis);
    words.expect("outer", "before a facet's corners");
    words.expect("loop", "after 'outer'");
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k) {
      words.expect("vertex", fmt::format("for corner {} of facet {}", k + 1, welder.mesh.triangles.size() + 1));
      const double x = words.number("a vertex x coordinate");
      const double y = words.number("a vertex y coordinate");
      const double z = words.number("a vertex z coordinate");
      tri[k] = welder.index(Vec3(x, y, z));
    }
    words.expect("endloop", "after a facet's three corners (only triangles are allowed)");
    words.expect("endfacet", "after 'endloop'");
    welder.mesh.triangles.push_back(tri);
  }
  return std::move(welder.mesh);
}

bool looks_ascii(std::string_view bytes) {
  std::size_t start = 0;
  while (start < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[start]))) ++start;
  return bytes.substr(start, 5) == "solid";
}

}  // namespace

TriangleMesh parse_stl(std::string_view bytes, std::string_view source) {
  if (bytes.empty()) throw ShapeError(fmt::format("{}: is empty; expected an STL surface", source));
  TriangleMesh mesh;
  std::uint32_t count = 0;
  const bool has_header = bytes.size() >= binary_header_bytes + binary_count_bytes;
  if (has_header) std::memcpy(&count, bytes.data() + binary_header_bytes, sizeof count);
  const std::size_t binary_size = binary_header_bytes + binary_count_bytes + std::size_t{count} * binary_triangle_bytes;
  if (has_header && bytes.size() == binary_size) {
    mesh = parse_binary(bytes, source, count);
  } else if (looks_ascii(bytes)) {
    mesh = parse_ascii(bytes, source);
  } else {
    if (!has_header)
      throw ShapeError(fmt::format("{}: is not an STL file: it does not start with 'solid' (ASCII STL) and is shorter "
                                   "({} bytes) than the 84-byte header of a binary STL",
                                   source, bytes.size()));
    throw ShapeError(fmt::format("{}: is not an STL file: it does not start with 'solid' (ASCII STL), and its size, {} "
                                 "bytes, does not match the {} triangles its binary header announces (84 + 50 x {} = {} "
                                 "bytes)",
                                 source, bytes.size(), count, count, binary_size));
  }
  check_closed(mesh, source);
  if (mesh_moments(mesh).volume < 0.0)
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

TriangleMesh read_stl(const std::filesystem::path& file) {
  std::error_code error;
  if (std::filesystem::is_directory(file, error))
    throw ShapeError(fmt::format("{}: is a directory; expected an STL surface", file.string()));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ShapeError(fmt::format("{}: cannot be opened (check the path); expected an STL surface", file.string()));
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parse_stl(bytes.str(), file.string());
}

std::string format_stl(const TriangleMesh& mesh, StlEncoding encoding, std::string_view solid_name) {
  auto normal_of = [&](const std::array<int, 3>& t) {
    const Vec3 n = (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    return n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3(Vec3::Zero());
  };
  std::string out;
  if (encoding == StlEncoding::ascii) {
    out += fmt::format("solid {}\n", solid_name);
    for (const auto& t : mesh.triangles) {
      const Vec3 n = normal_of(t);
      out += fmt::format("  facet normal {:.17g} {:.17g} {:.17g}\n    outer loop\n", n.x(), n.y(), n.z());
      for (int v : t) {
        const Vec3& p = mesh.vertices[v];
        out += fmt::format("      vertex {:.17g} {:.17g} {:.17g}\n", p.x(), p.y(), p.z());
      }
      out += "    endloop\n  endfacet\n";
    }
    out += fmt::format("endsolid {}\n", solid_name);
    return out;
  }
  std::string header = fmt::format("binary STL written by mfdem: {}", solid_name);
  header.resize(binary_header_bytes, ' ');
  out += header;
  const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  out.append(reinterpret_cast<const char*>(&count), sizeof count);
  for (const auto& t : mesh.triangles) {
    const Vec3 n = normal_of(t);
    std::array<float, 12> values{};
    for (int k = 0; k < 3; ++k) values[k] = static_cast<float>(n[k]);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) values[3 + 3 * c + k] = static_cast<float>(mesh.vertices[t[c]][k]);
    out.append(reinterpret_cast<const char*>(values.data()), sizeof values);
    out.append(2, '\0');  // attribute byte count
  }
  return out;
}

void write_stl(const TriangleMesh& mesh, const std::filesystem::path& file, StlEncoding encoding, std::string_view solid_name) {
  std::ofstream out(file, std::ios::binary);
  if (!out) throw ShapeError(fmt::format("{}: cannot be written", file.string()));
  const std::string bytes = format_stl(mesh, encoding, solid_name);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw ShapeError(fmt::format("{}: writing failed", file.string()));
}

}  // namespace mfdem::fidelity
