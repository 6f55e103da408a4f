// How a config value is quoted back to the user in an error message: as it would be written in
// TOML (shortest round-trip numbers, strings in double quotes), cut short when long.
#pragma once

#include <string>

#include <toml++/toml.h>

namespace mfdem::config::detail {

std::string value_text(const toml::node& node);

}  // namespace mfdem::config::detail
