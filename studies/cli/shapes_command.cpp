// `mfdem shapes`: build, list and describe the clump templates of the shape library.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "fidelity/shape_error.hpp"
#include "fidelity/shape_library.hpp"
#include "fidelity/template_file.hpp"
#include "studies/cli/app.hpp"
#include "studies/cli/subcommands.hpp"
#include "studies/config/config.hpp"

namespace mfdem::cli {

namespace {

namespace fs = std::filesystem;
using fidelity::ClumpTemplate;
using fidelity::ShapeLibrary;
using fidelity::ShapeSource;

constexpr int bad_input = 2;                     // as for config errors (app.hpp)
constexpr double ballast_density = 2800.0;       // kg/m^3, the paper's Table 1
constexpr double example_size_mm = 45.0;         // a typical 31.5/63 stone
constexpr long long max_pebbles = 1000;
constexpr long long max_grid_cells = 400;

fs::path default_settings() { return fidelity::standard_library_directory().parent_path() / "settings.toml"; }

struct NamedSource {
  std::string name;
  ShapeSource source;
};

// The packing settings of [library], which a [[stone]] may override.
ShapeSource read_packing(const config::Section& section, const ShapeSource& fallback) {
  ShapeSource s = fallback;
  s.packing.pebbles = static_cast<int>(
      section.integer_or("pebbles", fallback.packing.pebbles, {.min = 1, .max = max_pebbles}, "pebbles per clump"));
  s.packing.min_radius = section.number_or("min_radius", fallback.packing.min_radius, {.min = 0, .max = 0.5},
                                           "smallest pebble radius in units of the stone size d");
  s.packing.grid_cells = static_cast<int>(section.integer_or("grid_cells", fallback.packing.grid_cells,
                                                             {.min = 4, .max = max_grid_cells},
                                                             "bubble-pack grid cells along the longest side"));
  const std::string rule = section.choice("rule", {"largest_new_volume", "farthest_point"},
                                          fallback.packing.rule == fidelity::BubblePackRule::largest_new_volume
                                              ? "largest_new_volume"
                                              : "farthest_point");
  s.packing.rule = rule == "largest_new_volume" ? fidelity::BubblePackRule::largest_new_volume
                                                : fidelity::BubblePackRule::farthest_point;
  s.match_volume = section.boolean_or("match_volume", fallback.match_volume);
  return s;
}

std::vector<NamedSource> read_settings(const fs::path& file) {
  const config::Section top = config::load(file, "shape-library settings: [library] and [[stone]] tables");
  ShapeSource defaults;
  if (const auto library = top.optional_section("library")) defaults = read_packing(*library, defaults);
  std::vector<NamedSource> stones;
  for (const config::Section& stone : top.sections("stone")) {
    NamedSource named{stone.text("name"), read_packing(stone, defaults)};
    if (named.name.empty() || named.name.find_first_of("/\\ \t") != std::string::npos)
      stone.fail("name", "a template name must be non-empty, without spaces or slashes (it names a file)");
    for (const auto& other : stones)
      if (other.name == named.name) stone.fail("name", "each stone needs its own name");
    if (stone.has("stl")) {
      named.source.kind = ShapeSource::Kind::stl;
      named.source.stl_file = stone.text("stl");
    } else {
      auto& spec = named.source.stone;
      spec.name = named.name;
      spec.seed = static_cast<std::uint32_t>(stone.integer("seed", {.min = 0, .max = 4294967295.0}, "GSL seed"));
      spec.elongation = stone.number("elongation", {.min = 1}, "elongation L/I");
      spec.flatness = stone.number("flatness", {.min = 0, .max = 1, .min_exclusive = true}, "flatness S/I");
      spec.vertices = static_cast<int>(stone.integer("vertices", {.min = 8, .max = 1000}, "random points of the stone's hull"));
    }
    stones.push_back(std::move(named));
  }
  if (stones.empty()) top.fail("stone", "expected at least one [[stone]] table");
  top.finish();
  return stones;
}

std::string percent(double fraction, int decimals) { return fmt::format("{:+.{}f}", 100.0 * fraction, decimals); }

void print_table(std::ostream& out, const ShapeLibrary& library) {
  fmt::print(out, "{:<14} {:>7} {:>11} {:>13} {:>14} {:>13} {:>15} {:>13}\n", "name", "pebbles", "volume/d^3",
             "volume err %", "inertia err %", "protrusion/d", "elongation L/I", "flatness S/I");
  for (const auto& t : library.templates) {
    const bool fit = t.fit.has_value();
    fmt::print(out, "{:<14} {:>7} {:>11.4f} {:>13} {:>14} {:>13} {:>15} {:>13}\n", t.name, t.pebbles.size(), t.volume,
               fit ? percent(t.fit->volume_error, 3) : "-", fit ? fmt::format("{:.1f}", 100 * t.fit->inertia_error) : "-",
               fit ? fmt::format("{:.3f}", t.fit->protrusion) : "-",
               fit ? fmt::format("{:.2f}", t.fit->indices.elongation()) : "-",
               fit ? fmt::format("{:.2f}", t.fit->indices.flatness()) : "-");
  }
  out << "d: the stone's size, its intermediate dimension I (what a sieve measures); mass = density x volume x d^3.\n"
         "volume err: (V_clump - V_stone) / V_stone; inertia err: |I_clump - I_stone| / |I_stone| (tensors, Frobenius\n"
         "norm, same density); protrusion: how far pebbles reach outside the stone's surface. Clump mass properties\n"
         "integrate the union of the pebbles (overlaps counted once); the stone's follow exactly from its surface.\n";
}

void describe(std::ostream& out, const ClumpTemplate& t) {
  fmt::print(out, "clump template {}\n", t.name);
  if (t.source) {
    const ShapeSource& s = *t.source;
    if (s.kind == ShapeSource::Kind::generated)
      fmt::print(out, "  stone:       generated convex polyhedron, seed {}, elongation L/I {}, flatness S/I {}, {} hull points\n",
                 s.stone.seed, s.stone.elongation, s.stone.flatness, s.stone.vertices);
    else
      fmt::print(out, "  stone:       surface read from {}\n", s.stl_file);
    fmt::print(out, "  packing:     {} pebbles at most, rule {}, grid {} cells, smallest radius {} d, {}\n", s.packing.pebbles,
               s.packing.rule == fidelity::BubblePackRule::largest_new_volume ? "largest_new_volume" : "farthest_point",
               s.packing.grid_cells, s.packing.min_radius,
               s.match_volume ? "radii scaled to the stone's volume" : "inscribed pebbles");
  }
  fmt::print(out, "  body frame:  origin at the centre of mass, axes along the principal axes; lengths in units of d\n");
  fmt::print(out, "  volume:      {:.6f} d^3 (union of pebbles; integration error estimate {:.1e}, {} Sobol lines)\n",
             t.volume, t.integration.volume_error, t.integration.points);
  fmt::print(out, "  inertia:     {:.6e} {:.6e} {:.6e} rho d^5 (principal, ascending; error estimate {:.1e})\n",
             t.principal_inertia.x(), t.principal_inertia.y(), t.principal_inertia.z(), t.integration.inertia_error);
  fmt::print(out, "  input frame: centre of mass at ({:.6g}, {:.6g}, {:.6g}), rotation to body w x y z = ({:.6f}, {:.6f}, "
                  "{:.6f}, {:.6f}), size {:.6g}\n",
             t.centre_of_mass_input.x(), t.centre_of_mass_input.y(), t.centre_of_mass_input.z(), t.input_to_principal.w(),
             t.input_to_principal.x(), t.input_to_principal.y(), t.input_to_principal.z(), t.input_size);
  if (t.fit) {
    const auto& f = *t.fit;
    fmt::print(out, "  stone:       volume {:.6f} d^3, principal inertia {:.6e} {:.6e} {:.6e} rho d^5\n", f.volume,
               f.inertia(0, 0), f.inertia(1, 1), f.inertia(2, 2));
    fmt::print(out, "               L x I x S = {:.4f} x {:.4f} x {:.4f} d, elongation {:.3f}, flatness {:.3f}, {} faces\n",
               f.indices.length, f.indices.intermediate, f.indices.thickness, f.indices.elongation(), f.indices.flatness(),
               f.surface.triangles.size());
    fmt::print(out, "  fit:         volume error {}%, inertia error {:.2f}%, centroid offset {:.4f} d, protrusion {:.4f} d\n",
               percent(f.volume_error, 3), 100 * f.inertia_error, f.centroid.norm(), f.protrusion);
  }
  const double d = example_size_mm / 1000.0;
  const dem::Vec3 inertia = t.inertia(ballast_density, d);
  fmt::print(out, "  at d = {} mm, {} kg/m^3: mass {:.4f} kg, inertia {:.3e} {:.3e} {:.3e} kg m^2, equal-volume ball radius {:.2f} mm\n",
             example_size_mm, ballast_density, t.mass(ballast_density, d), inertia.x(), inertia.y(), inertia.z(),
             1000 * t.equivalent_radius(d));
  fmt::print(out, "  pebbles ({}):\n  {:>3} {:>10} {:>10} {:>10} {:>10}\n", t.pebbles.size(), "#", "x/d", "y/d", "z/d", "radius/d");
  for (std::size_t i = 0; i < t.pebbles.size(); ++i) {
    const auto& p = t.pebbles[i];
    fmt::print(out, "  {:>3} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f}\n", i + 1, p.centre.x(), p.centre.y(), p.centre.z(), p.radius);
  }
}

// Templates in `directory` that the new build does not write (a stone dropped from the settings).
void remove_stale_templates(const fs::path& directory, const std::vector<NamedSource>& stones, std::ostream& out) {
  std::error_code error;
  if (!fs::is_directory(directory, error)) return;
  for (const auto& entry : fs::directory_iterator(directory)) {
    if (entry.path().extension() != ".toml") continue;
    const std::string name = entry.path().stem().string();
    if (std::any_of(stones.begin(), stones.end(), [&](const auto& s) { return s.name == name; })) continue;
    try {
      fidelity::load_template(entry.path());
    } catch (const fidelity::ShapeError&) {
      continue;  // not a clump template: not ours to remove
    }
    fs::remove(entry.path());
    fmt::print(out, "removed {} (no longer in the settings)\n", entry.path().string());
  }
}

struct ShapesOptions {
  fs::path settings = default_settings();
  std::optional<int> pebbles;
  std::optional<fs::path> out;
  fs::path library = fidelity::standard_library_directory();
  std::string name;
};

int build(const ShapesOptions& options, std::ostream& out) {
  std::vector<NamedSource> stones = read_settings(options.settings);
  const int settings_pebbles = stones.front().source.packing.pebbles;
  if (options.pebbles)
    for (auto& stone : stones) stone.source.packing.pebbles = *options.pebbles;
  fs::path directory = fidelity::standard_library_directory();
  const bool shipped_settings =
      fs::exists(default_settings()) && fs::equivalent(options.settings, default_settings());
  if (options.out) directory = *options.out;
  else if (!shipped_settings)  // another library's settings: never into the shipped one
    directory = fs::current_path() / (options.settings.stem().string() + "_library");
  else if (options.pebbles && *options.pebbles != settings_pebbles)
    directory += fmt::format("_{}", *options.pebbles);  // never overwrite the shipped library by accident
  ShapeLibrary library;
  for (const auto& stone : stones) {
    library.templates.push_back(fidelity::build_template(stone.name, stone.source, options.settings.parent_path()));
    const auto& t = library.templates.back();
    fmt::print(out, "built {}: {} pebbles, volume error {}%, inertia error {:.1f}%\n", t.name, t.pebbles.size(),
               percent(t.fit->volume_error, 3), 100 * t.fit->inertia_error);
  }
  std::sort(library.templates.begin(), library.templates.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  remove_stale_templates(directory, stones, out);
  fidelity::save_library(library, directory);
  fmt::print(out, "wrote {} templates to {}\n\n", library.templates.size(), directory.string());
  print_table(out, library);
  return 0;
}

// Runs `body`, turning a bad shape file or setting into a message and exit status 2.
template <class Body>
int guarded(std::ostream& err, Body&& body) {
  try {
    return body();
  } catch (const fidelity::ShapeError& error) {
    print_error(err, error.what());
  } catch (const std::invalid_argument& error) {
    print_error(err, error.what());
  } catch (const std::out_of_range& error) {
    print_error(err, error.what());
  }
  return bad_input;
}

}  // namespace

void add_shapes_command(CLI::App& app, Action& action, std::ostream& out, std::ostream& err) {
  auto options = std::make_shared<ShapesOptions>();
  CLI::App* shapes = app.add_subcommand("shapes", "Build, list and describe the clump templates of the shape library");
  shapes->require_subcommand(1);
  shapes->footer(
      "Clump templates are ballast-like stones (seeded random convex polyhedra of given elongation and\n"
      "flatness, or STL surfaces) filled with overlapping pebbles. The shipped library is\n"
      "studies/shapes/library (6 pebbles per clump), built from studies/shapes/settings.toml.");

  CLI::App* build_command = shapes->add_subcommand("build", "Regenerate the library from its settings");
  build_command->footer(
      "Every stone of the settings is generated (or read from its STL file), filled with pebbles by\n"
      "bubble packing, and its mass properties integrated. Writes <name>.toml per template to --out\n"
      "(default: the shipped library, or <library>_N when --pebbles N differs from the settings;\n"
      "with other --settings, SETTINGS-STEM_library in the working folder),\n"
      "then prints the table of `mfdem shapes list`.");
  build_command->add_option("--settings", options->settings, "Settings file (TOML) of the library")
      ->capture_default_str();
  build_command->add_option("--pebbles", options->pebbles, "Pebbles per clump, for every stone (resolution)")
      ->check(CLI::Range(1, static_cast<int>(max_pebbles)));
  build_command->add_option("--out", options->out, "Directory to write the templates to");
  build_command->callback([options, &action, &out, &err] {
    action = [options, &out, &err] { return guarded(err, [&] { return build(*options, out); }); };
  });

  CLI::App* list = shapes->add_subcommand("list", "Table of the library's templates and their errors");
  list->add_option("--library", options->library, "Library directory")->capture_default_str();
  list->callback([options, &action, &out, &err] {
    action = [options, &out, &err] {
      return guarded(err, [&] {
        print_table(out, fidelity::load_library(options->library));
        return 0;
      });
    };
  });

  CLI::App* describe_command = shapes->add_subcommand("describe", "Everything about one template");
  describe_command->add_option("name", options->name, "Template name, e.g. ballast_01")->required();
  describe_command->add_option("--library", options->library, "Library directory")->capture_default_str();
  describe_command->callback([options, &action, &out, &err] {
    action = [options, &out, &err] {
      return guarded(err, [&] {
        describe(out, fidelity::load_library(options->library).at(options->name));
        return 0;
      });
    };
  });
}

}  // namespace mfdem::cli
