#pragma once
// Scene files: a TOML description of spheres, materials, walls and run settings that `mfdem run`
// simulates. The format is documented key by key in studies/scenes/*.toml and README.md.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "dem/simulation.hpp"

namespace mfdem::scene {

struct Scene {
  std::filesystem::path source;
  dem::Domain domain;
  dem::MaterialTable materials;
  dem::SimulationSettings settings;
  std::vector<dem::SphereSpec> spheres;
  std::vector<dem::ClumpSpec> clumps;
  std::vector<dem::PlaneWall> walls;
  double duration = 0.0;         // s
  double output_interval = 0.0;  // s
  std::uint64_t seed = 1;
};

// Reads and checks every key; throws config::ConfigError naming file, line, key and value.
// `seed` replaces the scene's own seed when given (the --seed option).
Scene load_scene(const std::filesystem::path& file, std::optional<std::uint64_t> seed = {});

// A solver set up with the scene's bodies and walls, ready for prepare().
dem::Simulation make_simulation(const Scene& scene);

}  // namespace mfdem::scene
