#include "fidelity/shape_library.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "fidelity/shape_error.hpp"
#include "fidelity/stl.hpp"
#include "fidelity/template_file.hpp"

#ifndef MFDEM_SHAPES_LIBRARY_DIR
#error "MFDEM_SHAPES_LIBRARY_DIR must name the shipped shape library (set in fidelity/CMakeLists.txt)"
#endif

namespace mfdem::fidelity {

const ClumpTemplate& ShapeLibrary::at(std::string_view name) const {
  const int index = index_of(name);
  if (index < 0) {
    std::vector<std::string> names;
    for (const auto& t : templates) names.push_back(t.name);
    throw std::out_of_range(fmt::format("no clump template '{}' in the library; it has: {}", name,
                                        names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "))));
  }
  return templates[index];
}

int ShapeLibrary::index_of(std::string_view name) const {
  for (std::size_t i = 0; i < templates.size(); ++i)
    if (templates[i].name == name) return static_cast<int>(i);
  return -1;
}

ClumpTemplate build_template(const std::string& name, const ShapeSource& source, const std::filesystem::path& base_dir) {
  TriangleMesh surface;
  if (source.kind == ShapeSource::Kind::generated) {
    StoneSpec stone = source.stone;
    stone.name = name;
    surface = generate_stone(stone);
  } else {
    surface = read_stl(base_dir / source.stl_file);
  }
  const double size = shape_indices(surface).intermediate;
  BubblePackOptions packing = source.packing;
  packing.min_radius *= size;
  std::vector<Pebble> pebbles = bubble_pack(surface, packing);
  if (pebbles.empty())
    throw std::invalid_argument(fmt::format("clump '{}': no pebble of radius >= {} d fits in the stone", name,
                                            source.packing.min_radius));
  if (source.match_volume) {
    const double factor = radius_factor_for_volume(pebbles, mesh_moments(surface).volume);
    for (auto& p : pebbles) p.radius *= factor;
  }
  ClumpTemplate clump = clump_from_pebbles(name, pebbles, size);
  fit_to_surface(clump, surface);
  clump.source = source;
  return clump;
}

ShapeLibrary load_library(const std::filesystem::path& directory) {
  std::error_code error;
  if (!std::filesystem::is_directory(directory, error))
    throw ShapeError(fmt::format("{}: is not a directory; expected a shape library (a directory of <name>.toml clump "
                                 "templates, made by 'mfdem shapes build')",
                                 directory.string()));
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(directory))
    if (entry.is_regular_file() && entry.path().extension() == ".toml") files.push_back(entry.path());
  if (files.empty())
    throw ShapeError(fmt::format("{}: holds no clump template (*.toml); build one with 'mfdem shapes build --out {}'",
                                 directory.string(), directory.string()));
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.filename() < b.filename(); });
  ShapeLibrary library;
  for (const auto& file : files) {
    ClumpTemplate clump = load_template(file);
    if (clump.name != file.stem().string())
      throw ShapeError(fmt::format("{}: holds template '{}'; a template file must be named after its template ({}.toml)",
                                   file.string(), clump.name, clump.name));
    library.templates.push_back(std::move(clump));
  }
  return library;
}

void save_library(const ShapeLibrary& library, const std::filesystem::path& directory) {
  std::filesystem::create_directories(directory);
  for (const auto& clump : library.templates) save_template(clump, directory / (clump.name + ".toml"));
}

std::filesystem::path standard_library_directory() { return MFDEM_SHAPES_LIBRARY_DIR; }

const ShapeLibrary& standard_library() {
  static const ShapeLibrary library = load_library(standard_library_directory());
  return library;
}

}  // namespace mfdem::fidelity
