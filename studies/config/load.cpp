#include "studies/config/load.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "studies/config/document.hpp"

namespace mfdem::config {

namespace {

constexpr std::string_view default_contents = "key = value settings and [tables]";

// TOML text holds no control characters but tab, line feed and carriage return; a NUL or any other
// C0 control byte means the file is not text at all (an HDF5 result, an image, a compressed file).
void reject_binary(std::string_view text, const std::string& source) {
  const auto binary = std::find_if(text.begin(), text.end(), [](char c) {
    const auto byte = static_cast<unsigned char>(c);
    return (byte < 0x20 && c != '\t' && c != '\n' && c != '\r') || byte == 0x7f;
  });
  if (binary == text.end()) return;
  const auto offset = static_cast<std::size_t>(binary - text.begin());
  const auto line = 1 + std::count(text.begin(), binary, '\n');
  throw ConfigError(fmt::format(
      "{}:{}: not a text file (binary byte 0x{:02x} at byte offset {}); expected a TOML config in UTF-8 text",
      source, line, static_cast<unsigned char>(*binary), offset));
}

bool blank(std::string_view text) {
  return std::all_of(text.begin(), text.end(), [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; });
}

}  // namespace

Section parse(std::string_view text, std::string source_name, std::string_view contents) {
  reject_binary(text, source_name);
  auto document = std::make_shared<detail::Document>();
  document->source = source_name;
  try {
    document->root = toml::parse(text, source_name);
  } catch (const toml::parse_error& error) {
    const auto& at = error.source().begin;
    const bool utf8 = error.description().find("utf-8") != std::string_view::npos;
    throw ConfigError(fmt::format("{}:{}:{}: TOML syntax error: {}{}", source_name, at.line, at.column,
                                  error.description(), utf8 ? " (save the file as UTF-8)" : ""));
  }
  if (document->root.empty())
    throw ConfigError(fmt::format("{}: {}; expected a TOML config with {}", source_name,
                                  blank(text) ? "is empty" : "holds only comments, no settings", contents));
  document->tables.push_back(detail::Table{&document->root, "", {}, {}});
  return Section(document, 0);
}

Section parse(std::string_view text, std::string source_name) {
  return parse(text, std::move(source_name), default_contents);
}

Section load(const std::filesystem::path& file, std::string_view contents) {
  const std::string source = file.string();
  std::error_code error;
  if (!std::filesystem::exists(file, error))
    throw ConfigError(fmt::format("{}: no such file; expected a TOML config file (check the path)", source));
  if (std::filesystem::is_directory(file, error))
    throw ConfigError(fmt::format("{}: is a directory; expected a TOML config file", source));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot be read: {}", source, std::strerror(errno)));
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw ConfigError(fmt::format("{}: reading failed: {}", source, std::strerror(errno)));
  return parse(text, source, contents);
}

Section load(const std::filesystem::path& file) { return load(file, default_contents); }

}  // namespace mfdem::config
