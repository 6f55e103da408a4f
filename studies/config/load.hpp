// Reading a TOML config file into a checked Section (see section.hpp).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "studies/config/section.hpp"

namespace mfdem::config {

// The top-level table of a config file. A missing or unreadable file, an empty one, binary data and
// TOML syntax errors all throw ConfigError naming the file (and the line, where there is one).
Section load(const std::filesystem::path& file);
// As above; `contents` says what the file should hold, for the message about an empty file,
// e.g. "a scene: [materials], [bed], [sleeper] and [push]".
Section load(const std::filesystem::path& file, std::string_view contents);

// The same checks on text already in memory; `source_name` stands for the file in messages.
Section parse(std::string_view text, std::string source_name);
Section parse(std::string_view text, std::string source_name, std::string_view contents);

}  // namespace mfdem::config
