// A checked view of one table of a TOML config file.
//
// Every getter names the key it reads; the section remembers each key asked for (found or not), so
// that finish() can reject keys the program never reads -- typos such as `[materails]` or
// `frcition = 0.5` -- and suggest the nearest known key. Every error is a ConfigError whose message
// names the file, the line, the full dotted key, the value found and what was expected, e.g.
//   scene.toml:14: materials.ballast.friction = -0.1: friction coefficient must be >= 0
//
// `meaning` says in physics words what a number is ("friction coefficient",
// "normal stiffness kn in N/m"); messages use it instead of the bare key.
// Numbers must be finite: TOML's inf and nan are rejected everywhere.
// Sections are cheap handles sharing the parsed file; copies share the record of asked keys.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "studies/config/config_error.hpp"
#include "studies/config/range.hpp"

namespace mfdem::config {

namespace detail {
struct Document;
struct Table;
}  // namespace detail

class Section {
 public:
  // Made by load() and parse(); `table` indexes the document's table records.
  Section(std::shared_ptr<detail::Document> document, std::size_t table);

  // A TOML integer or float; range bounds are checked.
  double number(std::string_view key, Range range = {}, std::string_view meaning = "") const;
  double number_or(std::string_view key, double fallback, Range range = {}, std::string_view meaning = "") const;
  // A TOML integer, or a float with no fractional part (so that `steps = 1e6` is accepted).
  long long integer(std::string_view key, Range range = {}, std::string_view meaning = "") const;
  long long integer_or(std::string_view key, long long fallback, Range range = {}, std::string_view meaning = "") const;
  bool boolean_or(std::string_view key, bool fallback) const;
  std::string text(std::string_view key) const;
  std::string text_or(std::string_view key, std::string fallback) const;
  // One of `allowed`; without a fallback the key is required.
  std::string choice(std::string_view key, std::vector<std::string> allowed,
                     std::optional<std::string> fallback = {}) const;
  // An array of exactly three numbers, e.g. gravity = [0, 0, -9.81].
  std::array<double, 3> vec3(std::string_view key, std::string_view meaning = "") const;
  std::array<double, 3> vec3_or(std::string_view key, std::array<double, 3> fallback, std::string_view meaning = "") const;
  std::vector<std::string> strings_or(std::string_view key, std::vector<std::string> fallback) const;

  // Whether the key is present; counts as asking for it.
  bool has(std::string_view key) const;
  // A required sub-table [path.key].
  Section section(std::string_view key) const;
  std::optional<Section> optional_section(std::string_view key) const;
  // An array of tables [[key]], in file order; empty when absent. Element i has path "key[i]"
  // (counted from 0).
  std::vector<Section> sections(std::string_view key) const;
  // The keys of a table whose keys are names chosen by the user ([materials.ballast],
  // [materials.sleeper]), in file order; all of them count as asked for.
  std::vector<std::string> names() const;

  // "scene.toml:12": where the key is, else where this table starts, else just the file.
  std::string where(std::string_view key) const;
  // Dotted path of this table: "" at the top level, "materials.ballast", "wall[2]".
  std::string path() const;
  // Throws a ConfigError "<where>: <path.key> = <value>: <expected>".
  [[noreturn]] void fail(std::string_view key, std::string_view expected) const;
  // Rejects every key of this table, and of the sub-tables opened from it, that was never asked
  // for; all such keys are reported at once, one per line, each with a suggestion.
  void finish() const;
  // Rejects at once (before the tables are read) a key of this table that is not one of `keys`:
  // a misspelt table such as [materails.small] is named as such, not as a material found missing
  // later.
  void expect_only(const std::vector<std::string>& keys) const;

 private:
  detail::Table& record() const;
  std::string key_path(std::string_view key) const;
  [[noreturn]] void missing(std::string_view key, std::string_view expected) const;
  void collect_unknown(std::vector<std::pair<std::size_t, std::string>>& found) const;

  std::shared_ptr<detail::Document> document_;
  std::size_t table_;
};

}  // namespace mfdem::config
