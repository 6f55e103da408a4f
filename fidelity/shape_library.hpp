#pragma once
// The shape library: clump templates of ballast-like stones, one TOML file per template.
//
// A library is a directory of template files (template_file.hpp), e.g. studies/shapes/library/;
// its templates are ordered by name, and a template's index in that order is what StoneSampler
// draws, so the same library gives the same stones. The shipped library is built from
// studies/shapes/settings.toml by `mfdem shapes build`; each file also records the settings that
// made it ([source]), so any template can be rebuilt from its own file.
//
// From C++:
//   const auto& library = mfdem::fidelity::standard_library();   // the shipped 6-pebble library
//   const auto& stone = library.templates[k];                     // or library.at("ballast_07")
//   auto lib = mfdem::fidelity::load_library("studies/shapes/library_fine");
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "fidelity/clump_template.hpp"

namespace mfdem::fidelity {

struct ShapeLibrary {
  std::vector<ClumpTemplate> templates;  // ordered by name

  // Throws std::out_of_range naming the templates there are.
  const ClumpTemplate& at(std::string_view name) const;
  int index_of(std::string_view name) const;  // -1 when absent
};

// Builds one template from its settings: the stone's surface (generated, or read from
// `base_dir / source.stl_file`), scaled so that its size I is 1, bubble-packed with
// source.packing (min_radius in units of the size), its union integrated, and its fit to the
// surface measured.
ClumpTemplate build_template(const std::string& name, const ShapeSource& source,
                             const std::filesystem::path& base_dir = {});

// Every *.toml file of the directory, ordered by name. Throws ShapeError naming the directory
// when there is none, or the file and key of the first problem.
ShapeLibrary load_library(const std::filesystem::path& directory);
// Writes one file per template, <name>.toml, creating the directory when needed.
void save_library(const ShapeLibrary& library, const std::filesystem::path& directory);

// Where the shipped library lives (studies/shapes/library of the source tree this was built from).
std::filesystem::path standard_library_directory();
// The shipped library, loaded on first use.
const ShapeLibrary& standard_library();

}  // namespace mfdem::fidelity
