#include "studies/config/section.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "studies/config/document.hpp"
#include "studies/config/nearest.hpp"
#include "studies/config/value_text.hpp"

namespace mfdem::config {

namespace {

// Largest magnitude below which every whole number is exactly a double: 2^53.
constexpr double max_exact_integer = 9007199254740992.0;

bool is_bare_key(std::string_view key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

std::string key_text(std::string_view key) {
  return is_bare_key(key) ? std::string(key) : fmt::format("\"{}\"", key);
}

// "expected a number (friction coefficient)"
std::string expected(std::string_view kind, std::string_view meaning) {
  return meaning.empty() ? fmt::format("expected {}", kind) : fmt::format("expected {} ({})", kind, meaning);
}

std::string one_of(const std::vector<std::string>& allowed) {
  std::vector<std::string> quoted;
  for (const auto& a : allowed) quoted.push_back(fmt::format("\"{}\"", a));
  return fmt::format("one of {}", fmt::join(quoted, ", "));
}

std::size_t line_of(const toml::source_region& region) { return region.begin.line; }

std::optional<double> finite_number(const toml::node& node) {
  std::optional<double> x;
  if (auto i = node.as_integer()) x = static_cast<double>(i->get());
  if (auto f = node.as_floating_point()) x = f->get();
  if (x && !std::isfinite(*x)) return std::nullopt;
  return x;
}

}  // namespace

Section::Section(std::shared_ptr<detail::Document> document, std::size_t table)
    : document_(std::move(document)), table_(table) {}

detail::Table& Section::record() const { return document_->tables[table_]; }

std::string Section::path() const { return record().path; }

std::string Section::key_path(std::string_view key) const {
  return path().empty() ? key_text(key) : fmt::format("{}.{}", path(), key_text(key));
}

std::string Section::where(std::string_view key) const {
  const toml::table& table = *record().table;
  std::size_t line = 0;
  if (auto it = table.find(key); it != table.end()) line = line_of(it->first.source());
  if (line == 0 && table_ != 0) line = line_of(table.source());
  return line == 0 ? document_->source : fmt::format("{}:{}", document_->source, line);
}

void Section::fail(std::string_view key, std::string_view expected_text) const {
  record().asked.emplace(key);
  if (const toml::node* node = record().table->get(key))
    throw ConfigError(fmt::format("{}: {} = {}: {}", where(key), key_path(key), detail::value_text(*node), expected_text));
  throw ConfigError(fmt::format("{}: {}: {}", where(key), key_path(key), expected_text));
}

void Section::missing(std::string_view key, std::string_view expected_text) const {
  const std::string table = path().empty() ? "[top level]" : fmt::format("[{}]", path());
  // A key of the table that is read by nothing and spelt nearly as the missing one: its typo.
  std::string hint;
  for (auto&& [present, value] : *record().table)
    if (!record().asked.count(present.str()) && nearest(present.str(), {std::string(key)})) {
      hint = fmt::format("; line {} has '{}', which nothing reads: did you mean '{}'?", line_of(present.source()),
                         key_text(present.str()), key_text(key));
      break;
    }
  throw ConfigError(
      fmt::format("{}: missing key '{}' in {}: {}{}", where(key), key_text(key), table, expected_text, hint));
}

void Section::expect_only(const std::vector<std::string>& keys) const {
  const std::string label = path().empty() ? "[top level]" : fmt::format("[{}]", path());
  for (auto&& [key, value] : *record().table) {
    if (std::find(keys.begin(), keys.end(), key.str()) != keys.end()) continue;
    const auto suggestion = nearest(key.str(), keys);
    throw ConfigError(fmt::format("{}: unknown key '{}' in {}; {}", where(key.str()), key_text(key.str()), label,
                                  suggestion ? fmt::format("did you mean '{}'?", *suggestion)
                                             : fmt::format("expected one of: {}", fmt::join(keys, ", "))));
  }
}

bool Section::has(std::string_view key) const {
  record().asked.emplace(key);
  return record().table->contains(key);
}

double Section::number(std::string_view key, Range range, std::string_view meaning) const {
  if (!has(key)) missing(key, expected("a number", meaning));
  const toml::node& node = *record().table->get(key);
  if (!node.is_number()) fail(key, expected("a number", meaning));
  const std::optional<double> x = finite_number(node);
  if (!x) fail(key, expected("a finite number", meaning));
  if (!contains(range, *x))
    fail(key, fmt::format("{} must be {}", meaning.empty() ? key : meaning, describe(range)));
  return *x;
}

double Section::number_or(std::string_view key, double fallback, Range range, std::string_view meaning) const {
  return has(key) ? number(key, range, meaning) : fallback;
}

long long Section::integer(std::string_view key, Range range, std::string_view meaning) const {
  if (!has(key)) missing(key, expected("a whole number", meaning));
  const toml::node& node = *record().table->get(key);
  long long n = 0;
  if (auto i = node.as_integer()) {
    n = i->get();
  } else {
    const std::optional<double> x = node.is_floating_point() ? finite_number(node) : std::nullopt;
    if (!x || std::trunc(*x) != *x || std::abs(*x) > max_exact_integer) fail(key, expected("a whole number", meaning));
    n = static_cast<long long>(*x);
  }
  if (!contains(range, static_cast<double>(n)))
    fail(key, fmt::format("{} must be {}", meaning.empty() ? key : meaning, describe(range)));
  return n;
}

long long Section::integer_or(std::string_view key, long long fallback, Range range, std::string_view meaning) const {
  return has(key) ? integer(key, range, meaning) : fallback;
}

bool Section::boolean_or(std::string_view key, bool fallback) const {
  if (!has(key)) return fallback;
  auto value = record().table->get(key)->as_boolean();
  if (!value) fail(key, "expected true or false");
  return value->get();
}

std::string Section::text(std::string_view key) const {
  if (!has(key)) missing(key, "expected text in double quotes");
  auto value = record().table->get(key)->as_string();
  if (!value) fail(key, "expected text in double quotes");
  return value->get();
}

std::string Section::text_or(std::string_view key, std::string fallback) const {
  return has(key) ? text(key) : fallback;
}

std::string Section::choice(std::string_view key, std::vector<std::string> allowed,
                            std::optional<std::string> fallback) const {
  if (!has(key)) {
    if (fallback) return *fallback;
    missing(key, "expected " + one_of(allowed));
  }
  auto value = record().table->get(key)->as_string();
  if (!value) fail(key, "expected " + one_of(allowed));
  if (std::find(allowed.begin(), allowed.end(), value->get()) != allowed.end()) return value->get();
  const auto suggestion = nearest(value->get(), allowed);
  fail(key, "expected " + one_of(allowed) + (suggestion ? fmt::format("; did you mean \"{}\"?", *suggestion) : ""));
}

std::array<double, 3> Section::vec3(std::string_view key, std::string_view meaning) const {
  const std::string kind = "3 finite numbers [x, y, z]";
  if (!has(key)) missing(key, expected(kind, meaning));
  auto array = record().table->get(key)->as_array();
  if (!array || array->size() != 3) fail(key, expected(kind, meaning));
  std::array<double, 3> v{};
  for (std::size_t i = 0; i < 3; ++i) {
    const std::optional<double> x = finite_number(*array->get(i));
    if (!x) fail(key, expected(kind, meaning));
    v[i] = *x;
  }
  return v;
}

std::array<double, 3> Section::vec3_or(std::string_view key, std::array<double, 3> fallback, std::string_view meaning) const {
  return has(key) ? vec3(key, meaning) : fallback;
}

std::vector<std::string> Section::strings_or(std::string_view key, std::vector<std::string> fallback) const {
  if (!has(key)) return fallback;
  const std::string kind = "expected a list of text strings, e.g. [\"a\", \"b\"]";
  auto array = record().table->get(key)->as_array();
  if (!array) fail(key, kind);
  std::vector<std::string> out;
  for (const toml::node& element : *array) {
    auto value = element.as_string();
    if (!value) fail(key, kind);
    out.push_back(value->get());
  }
  return out;
}

Section Section::section(std::string_view key) const {
  const std::string full = key_path(key);
  if (!has(key)) missing(key, fmt::format("expected a table [{}]", full));
  auto table = record().table->get(key)->as_table();
  if (!table) fail(key, fmt::format("expected a table [{}]", full));
  return Section(document_, document_->open(*table, full, table_));
}

std::optional<Section> Section::optional_section(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return section(key);
}

std::vector<Section> Section::sections(std::string_view key) const {
  std::vector<Section> out;
  if (!has(key)) return out;
  const std::string full = key_path(key);
  auto array = record().table->get(key)->as_array();
  const std::string kind = fmt::format("expected an array of tables, each starting with [[{}]]", full);
  if (!array) fail(key, kind);
  for (std::size_t i = 0; i < array->size(); ++i) {
    auto table = array->get(i)->as_table();
    if (!table) fail(key, kind);
    out.emplace_back(document_, document_->open(*table, fmt::format("{}[{}]", full, i), table_));
  }
  return out;
}

std::vector<std::string> Section::names() const {
  std::vector<const toml::key*> keys;
  for (auto&& [key, value] : *record().table) keys.push_back(&key);
  std::stable_sort(keys.begin(), keys.end(), [](const toml::key* a, const toml::key* b) {
    const auto pa = a->source().begin, pb = b->source().begin;
    return pa.line != pb.line ? pa.line < pb.line : pa.column < pb.column;
  });
  std::vector<std::string> out;
  for (const toml::key* key : keys) {
    record().asked.emplace(key->str());
    out.emplace_back(key->str());
  }
  return out;
}

void Section::collect_unknown(std::vector<std::pair<std::size_t, std::string>>& found) const {
  const detail::Table& table = record();
  const std::vector<std::string> known(table.asked.begin(), table.asked.end());
  const std::string label = table.path.empty() ? "[top level]" : fmt::format("[{}]", table.path);
  for (auto&& [key, value] : *table.table) {
    if (table.asked.count(key.str())) continue;
    std::string hint;
    if (auto suggestion = nearest(key.str(), known)) hint = fmt::format("did you mean '{}'?", *suggestion);
    else if (known.empty()) hint = fmt::format("nothing is read from {}", label);
    else hint = fmt::format("expected one of: {}", fmt::join(known, ", "));
    found.emplace_back(line_of(key.source()),
                       fmt::format("{}: unknown key '{}' in {}; {}", where(key.str()), key_text(key.str()), label, hint));
  }
  for (std::size_t child : table.opened) Section(document_, child).collect_unknown(found);
}

void Section::finish() const {
  std::vector<std::pair<std::size_t, std::string>> found;
  collect_unknown(found);
  if (found.empty()) return;
  std::stable_sort(found.begin(), found.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string message;
  for (const auto& [line, text] : found) message += (message.empty() ? "" : "\n") + text;
  throw ConfigError(message);
}

}  // namespace mfdem::config
