// A mistake in a config file. Its message is meant for the user as is: it names the file, the
// line, the dotted key, the value found and what was expected, e.g.
//   scene.toml:14: materials.ballast.friction = -0.1: friction coefficient must be >= 0
// The command line turns it into exit status 2.
#pragma once

#include <stdexcept>

namespace mfdem::config {

struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace mfdem::config
