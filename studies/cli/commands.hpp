// What the `mfdem` subcommands are given, and the functions that carry them out.
#pragma once

#include <cstdint>
#include <filesystem>

namespace mfdem {

// Options shared by every subcommand that simulates (see common_options.hpp).
struct CommonOptions {
  int threads = 0;  // OpenMP threads; 0 = all cores
  std::uint64_t seed = 1;
  std::filesystem::path out = "out";
  bool quiet = false;
  bool seed_given = false;  // --seed was on the command line (else the scene's own seed may apply)
};

struct RunOptions {
  CommonOptions common;
  std::filesystem::path scene;
  bool force_dt = false;  // keep the scene's time step even above the stability estimate
};

// `mfdem run`: simulate a scene file; returns the process exit status.
int run_scene_command(const RunOptions& options);

// `mfdem check`: validate a scene file completely; throws config::ConfigError on the first problem.
void check_scene_file(const std::filesystem::path& file);

}  // namespace mfdem
