// `mfdem shapes build | list | describe`, run as a user would.
#include <catch2/catch.hpp>

#include <regex>
#include <sstream>

#include <fmt/format.h>

#include "fidelity/shape_library.hpp"
#include "fidelity/stl.hpp"
#include "fidelity/stone_generator.hpp"
#include "tests/support/run_mfdem.hpp"

using mfdem::test::run_mfdem;
using mfdem::test::TempDir;
using Catch::Contains;
using Catch::StartsWith;

namespace {

constexpr int bad_input = 2;

// Rows of the table: lines that start with a template name.
std::vector<std::string> table_rows(const std::string& text, const std::string& prefix) {
  std::vector<std::string> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(prefix, 0) == 0) rows.push_back(line);
  return rows;
}

}  // namespace

TEST_CASE("mfdem shapes list prints one row per shipped template", "[fidelity][shapes-cli]") {
  const auto result = run_mfdem({"shapes", "list"});
  REQUIRE(result.status == 0);
  CHECK_THAT(result.out, StartsWith("name ") && Contains("pebbles") && Contains("volume err %") &&
                             Contains("inertia err %") && Contains("elongation L/I") && Contains("flatness S/I"));
  const auto rows = table_rows(result.out, "ballast_");
  REQUIRE(rows.size() == mfdem::fidelity::standard_library().templates.size());
  // ballast_01: 6 pebbles, its volume and its elongation 1.25 / flatness 0.80 from the settings.
  const auto& t = mfdem::fidelity::standard_library().at("ballast_01");
  CHECK(std::regex_search(rows[0], std::regex(fmt::format(R"(^ballast_01\s+6\s+{:.4f}\s.*\s1\.25\s+0\.80$)", t.volume))));
}

TEST_CASE("mfdem shapes describe shows the pebbles and the mass at a ballast size", "[fidelity][shapes-cli]") {
  const auto result = run_mfdem({"shapes", "describe", "ballast_03"});
  REQUIRE(result.status == 0);
  const auto& t = mfdem::fidelity::standard_library().at("ballast_03");
  CHECK_THAT(result.out, StartsWith("clump template ballast_03\n") && Contains("pebbles (6):") &&
                             Contains(fmt::format("mass {:.4f} kg", t.mass(2800.0, 0.045))));
  const auto unknown = run_mfdem({"shapes", "describe", "granite"});
  CHECK(unknown.status == bad_input);
  CHECK_THAT(unknown.err, StartsWith("mfdem: error: no clump template 'granite' in the library"));
}

TEST_CASE("mfdem shapes build makes a library from settings, with generated and STL stones", "[fidelity][shapes-cli]") {
  const TempDir dir;
  mfdem::fidelity::write_stl(mfdem::fidelity::generate_stone({"scan", 5, 1.4, 0.7, 12}), dir.path() / "scan.stl",
                             mfdem::fidelity::StlEncoding::binary);
  const auto settings = dir.write("settings.toml",
                                  "[library]\npebbles = 3\ngrid_cells = 20\n\n"
                                  "[[stone]]\nname = \"gen\"\nseed = 3\nelongation = 1.5\nflatness = 0.6\nvertices = 12\n\n"
                                  "[[stone]]\nname = \"scan\"\nstl = \"scan.stl\"\npebbles = 4\n");
  const auto out = dir.path() / "lib";
  const auto result = run_mfdem({"shapes", "build", "--settings", settings.string(), "--out", out.string()});
  INFO(result.err);
  REQUIRE(result.status == 0);
  CHECK_THAT(result.out, Contains("wrote 2 templates to " + out.string()));
  const auto library = mfdem::fidelity::load_library(out);
  REQUIRE(library.templates.size() == 2);
  CHECK(library.at("gen").pebbles.size() == 3);
  CHECK(library.at("scan").pebbles.size() == 4);
  CHECK(library.at("scan").fit->indices.elongation() == Approx(1.4).epsilon(1e-6));  // float STL, unit I
  CHECK(std::abs(library.at("scan").fit->volume_error) < 1e-4);
  // --pebbles overrides the settings for every stone.
  const auto finer = run_mfdem({"shapes", "build", "--settings", settings.string(), "--out", out.string(), "--pebbles", "5"});
  REQUIRE(finer.status == 0);
  CHECK(mfdem::fidelity::load_library(out).at("scan").pebbles.size() == 5);

  // Without --out, another library's settings build into the working folder, never into the
  // shipped library (which stays as it was).
  const auto shipped = mfdem::fidelity::load_library(mfdem::fidelity::standard_library_directory());
  const auto here = run_mfdem({"shapes", "build", "--settings", settings.string()}, dir.path().string());
  REQUIRE(here.status == 0);
  CHECK_THAT(here.out, Contains("wrote 2 templates to " + (dir.path() / "settings_library").string()));
  CHECK(mfdem::fidelity::load_library(dir.path() / "settings_library").templates.size() == 2);
  const auto after = mfdem::fidelity::load_library(mfdem::fidelity::standard_library_directory());
  REQUIRE(after.templates.size() == shipped.templates.size());
  for (std::size_t k = 0; k < after.templates.size(); ++k) CHECK(after.templates[k].name == shipped.templates[k].name);
}

TEST_CASE("mfdem shapes build reports a bad setting with file, line and key", "[fidelity][shapes-cli]") {
  const TempDir dir;
  const auto typo = dir.write("settings.toml", "[[stone]]\nname = \"a\"\nseed = 1\nelongation = 1.5\nflatnes = 0.6\nvertices = 12\n");
  const auto result = run_mfdem({"shapes", "build", "--settings", typo.string(), "--out", (dir.path() / "lib").string()});
  CHECK(result.status == bad_input);
  CHECK_THAT(result.err, Contains(typo.string() + ":") && Contains("flatness"));
  const auto range = dir.write("range.toml", "[[stone]]\nname = \"a\"\nseed = 1\nelongation = 0.5\nflatness = 0.6\nvertices = 12\n");
  const auto ranged = run_mfdem({"shapes", "build", "--settings", range.string(), "--out", (dir.path() / "lib").string()});
  CHECK(ranged.status == bad_input);
  CHECK_THAT(ranged.err, Contains(range.string() + ":4") && Contains("elongation") && Contains(">= 1"));
  const auto open = dir.write("open.toml", "[[stone]]\nname = \"o\"\nstl = \"open.stl\"\n");
  dir.write("open.stl", "solid o\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid o\n");
  const auto opened = run_mfdem({"shapes", "build", "--settings", open.string(), "--out", (dir.path() / "lib").string()});
  CHECK(opened.status == bad_input);
  CHECK_THAT(opened.err, Contains((dir.path() / "open.stl").string() + ": the surface is open (not watertight)"));
}
