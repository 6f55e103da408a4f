// Reading config files: every file-level failure is a ConfigError naming the file.
#include <catch2/catch.hpp>

#include "studies/config/config.hpp"
#include "tests/support/temp_dir.hpp"

using mfdem::config::ConfigError;
using mfdem::config::load;
using mfdem::config::parse;
using mfdem::test::TempDir;
using Catch::Matchers::Message;

TEST_CASE("a valid file loads and reads", "[config]") {
  const TempDir dir;
  const auto file = dir.write("scene.toml", "[sleeper]\nmass = 380\n");
  const auto top = load(file);
  CHECK(top.section("sleeper").number("mass") == 380.0);
  CHECK(top.section("sleeper").where("mass") == file.string() + ":2");
}

TEST_CASE("a missing file is named with the advice to check the path", "[config]") {
  const TempDir dir;
  const auto file = dir.path() / "missing.toml";
  CHECK_THROWS_MATCHES(load(file), ConfigError,
                       Message(file.string() + ": no such file; expected a TOML config file (check the path)"));
}

TEST_CASE("a directory is not a config file", "[config]") {
  const TempDir dir;
  CHECK_THROWS_MATCHES(load(dir.path()), ConfigError,
                       Message(dir.path().string() + ": is a directory; expected a TOML config file"));
}

TEST_CASE("an empty file says what it should hold", "[config]") {
  const TempDir dir;
  const auto file = dir.write("empty.toml", "");
  CHECK_THROWS_MATCHES(load(file), ConfigError,
                       Message(file.string() + ": is empty; expected a TOML config with key = value settings and [tables]"));
  CHECK_THROWS_MATCHES(load(file, "a scene: [materials], [bed], [sleeper] and [push]"), ConfigError,
                       Message(file.string() + ": is empty; expected a TOML config with a scene: [materials], [bed], [sleeper] and [push]"));
  CHECK_THROWS_MATCHES(parse(" \n\t\n", "blank.toml"), ConfigError,
                       Message("blank.toml: is empty; expected a TOML config with key = value settings and [tables]"));
}

TEST_CASE("a file of comments only has no settings", "[config]") {
  CHECK_THROWS_MATCHES(parse("# gravity = 9.81\n", "notes.toml"), ConfigError,
                       Message("notes.toml: holds only comments, no settings; expected a TOML config with key = value settings and [tables]"));
}

TEST_CASE("binary data is rejected as not a text file", "[config]") {
  const TempDir dir;
  // The first bytes of a PNG image: a NUL-free high byte, "PNG", CR LF, then SUB (0x1a) on line 2.
  const std::string png("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16);
  const auto file = dir.write("image.toml", png);
  CHECK_THROWS_MATCHES(load(file), ConfigError,
                       Message(file.string() + ":2: not a text file (binary byte 0x1a at byte offset 6); "
                                               "expected a TOML config in UTF-8 text"));
  const std::string nul("a = 1\n\0b = 2\n", 13);
  CHECK_THROWS_MATCHES(parse(nul, "nul.toml"), ConfigError,
                       Message("nul.toml:2: not a text file (binary byte 0x00 at byte offset 6); expected a TOML config in UTF-8 text"));
}

TEST_CASE("a TOML syntax error names file line and column", "[config]") {
  // Column 8 is the line end right after "mass = ", where a value was due.
  CHECK_THROWS_MATCHES(parse("title = \"demo\"\nmass = \n", "scene.toml"), ConfigError,
                       Message("scene.toml:2:8: TOML syntax error: Error while parsing key-value pair: expected value, saw '\\n'"));
  CHECK_THROWS_MATCHES(parse("a = 1\na = 2\n", "scene.toml"), ConfigError,
                       Message("scene.toml:2:5: TOML syntax error: Error while parsing key-value pair: cannot redefine existing integer 'a'"));
}

TEST_CASE("text that is not UTF-8 asks for UTF-8", "[config]") {
  // "caf\xe9" is Latin-1 for cafe with an accent: the byte 0xe9 starts no valid UTF-8 sequence here.
  CHECK_THROWS_WITH(parse("name = \"caf\xe9\"\n", "latin1.toml"),
                    Catch::Matchers::StartsWith("latin1.toml:1:") && Catch::Matchers::EndsWith("(save the file as UTF-8)"));
}
