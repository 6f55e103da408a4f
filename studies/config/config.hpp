// The config checker in one include: load()/parse() a TOML file, read it through Section getters,
// then finish() to reject unknown keys.
#pragma once

#include "studies/config/config_error.hpp"  // IWYU pragma: export
#include "studies/config/load.hpp"          // IWYU pragma: export
#include "studies/config/range.hpp"         // IWYU pragma: export
#include "studies/config/section.hpp"       // IWYU pragma: export
