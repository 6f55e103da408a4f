#include "studies/config/value_text.hpp"

#include <sstream>

#include <fmt/format.h>

namespace mfdem::config::detail {

namespace {

constexpr std::size_t max_length = 60;  // characters of a value shown in a one-line message

std::string shortened(std::string text) {
  if (text.size() <= max_length) return text;
  return text.substr(0, max_length - 3) + "...";
}

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else out += c;
  }
  return out + "\"";
}

std::string full_text(const toml::node& node) {
  if (auto v = node.as_integer()) return fmt::format("{}", v->get());
  if (auto v = node.as_floating_point()) return fmt::format("{}", v->get());
  if (auto v = node.as_boolean()) return v->get() ? "true" : "false";
  if (auto v = node.as_string()) return quoted(v->get());
  if (auto array = node.as_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < array->size() && out.size() <= max_length; ++i)
      out += (i ? ", " : "") + full_text(*array->get(i));
    return out + "]";
  }
  if (node.is_table()) return "{...} (a table)";
  std::ostringstream date_or_time;  // the remaining TOML types print themselves as written
  node.visit([&](const auto& value) { date_or_time << value; });
  return date_or_time.str();
}

}  // namespace

std::string value_text(const toml::node& node) { return shortened(full_text(node)); }

}  // namespace mfdem::config::detail
