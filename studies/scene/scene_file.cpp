#include "studies/scene/scene_file.hpp"

#include <cmath>

#include <fmt/format.h>

#include <algorithm>

#include "dem/state_file.hpp"
#include "studies/config/config.hpp"
#include "studies/scene/clump_source.hpp"
#include "studies/scene/material_keys.hpp"
#include "studies/scene/sphere_sources.hpp"
#include "studies/scene/stone_sources.hpp"

namespace mfdem::scene {
namespace {

using config::Range;
using config::Section;

dem::Vec3 to_vec(const std::array<double, 3>& a) { return dem::Vec3(a[0], a[1], a[2]); }

const Range kPositive{.min = 0.0, .min_exclusive = true};
const Range kNonNegative{.min = 0.0};

void read_simulation(const Section& s, Scene& scene) {
  scene.duration = s.number("duration", kPositive, "simulated time in s");
  scene.settings.time_step = s.number_or("time_step", 0.0, kNonNegative,
                                         "time step in s (0 or absent: automatic)");
  scene.settings.time_step_safety = s.number_or("time_step_safety", 0.2,
                                                {.min = 0.0, .max = 1.0, .min_exclusive = true},
                                                "fraction of the critical time step");
  scene.settings.force_time_step = s.boolean_or("force_time_step", false);
  scene.output_interval = s.number_or("output_interval", scene.duration / 20.0, kPositive,
                                      "output interval in s");
  scene.settings.gravity = to_vec(s.vec3_or("gravity", {0.0, 0.0, -9.81}, "gravity in m/s^2"));
  scene.settings.skin = s.number_or("skin", 0.0, kNonNegative,
                                    "neighbour-list skin in m (0: 0.2 x smallest radius)");
  scene.seed = static_cast<std::uint64_t>(s.integer_or("seed", 1, {.min = 0}, "random seed"));
}

void read_domain(const Section& s, dem::Domain& d) {
  d.min = to_vec(s.vec3("min", "domain corner in m"));
  d.max = to_vec(s.vec3("max", "domain corner in m"));
  for (int a = 0; a < 3; ++a)
    if (!(d.max[a] > d.min[a]))
      s.fail("max", fmt::format("a corner above min along {} (min = {})", "xyz"[a], d.min[a]));
  for (const auto& axis : s.strings_or("periodic", {})) {
    if (axis != "x" && axis != "y" && axis != "z")
      s.fail("periodic", "a list of axis names among \"x\", \"y\", \"z\"");
    d.periodic[axis[0] - 'x'] = true;
  }
}

void read_walls(const Section& s, int index, Scene& scene) {
  const std::string type = s.choice("type", {"plane", "box"});
  const int material = material_key(s, scene.materials);
  const std::string name = s.text_or("name", fmt::format("wall{}", index));
  if (type == "plane") {
    dem::PlaneWall w;
    w.name = name;
    w.point = to_vec(s.vec3("point", "a point on the plane in m"));
    w.normal = to_vec(s.vec3("normal", "normal pointing into the domain"));
    if (w.normal.norm() == 0.0) s.fail("normal", "a non-zero vector");
    w.velocity = to_vec(s.vec3_or("velocity", {0, 0, 0}, "wall velocity in m/s"));
    w.material = material;
    scene.walls.push_back(w);
    return;
  }
  const dem::Vec3 lo = to_vec(s.vec3("min", "box corner in m"));
  const dem::Vec3 hi = to_vec(s.vec3("max", "box corner in m"));
  for (int a = 0; a < 3; ++a)
    if (!(hi[a] > lo[a])) s.fail("max", fmt::format("a corner above min along {}", "xyz"[a]));
  const bool open_top = s.boolean_or("open_top", true);
  for (const auto& w : dem::box_walls(name, lo, hi, open_top, material)) scene.walls.push_back(w);
}

// [[state_file]]: every body of one frame of an earlier run's state.h5 (a settled packing):
// path (relative to the scene file), frame (default -1: the last). Materials are matched by name.
void read_state_file(const Section& s, Scene& scene) {
  const std::filesystem::path file = path_beside_scene(s, "path");
  long long frame = s.integer_or("frame", -1, {}, "frame index (negative counts from the end)");
  dem::StateFrame f;
  try {
    const int frames = dem::count_frames(file);
    if (frame < 0) frame += frames;
    if (frame < 0 || frame >= frames)
      s.fail("frame", fmt::format("a frame of {} (it has {})", file.string(), frames));
    f = dem::read_frame(file, static_cast<int>(frame));
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const config::ConfigError*>(&e)) throw;
    s.fail("path", fmt::format("an mfdem state file ({})", e.what()));
  }
  try {
    dem::require_valid_frame(f);
  } catch (const std::invalid_argument& e) {
    s.fail("path", fmt::format("a state file with {} (frame {} of {})", e.what(), frame, file.string()));
  }
  std::vector<int> material_of;
  for (const auto& name : f.material_names) {
    const int m = scene.materials.index_of(name);
    material_of.push_back(m);
  }
  for (std::size_t e = 0; e < f.element_material.size(); ++e)
    if (material_of[f.element_material[e]] < 0)
      s.fail("path", fmt::format("a packing whose materials the scene defines (material '{}' of {} is "
                                 "not under [materials])",
                                 f.material_names[f.element_material[e]], file.string()));
  for (auto& body : dem::bodies_of(f, material_of)) scene.clumps.push_back(std::move(body));
}

}  // namespace

Scene load_scene(const std::filesystem::path& file, std::optional<std::uint64_t> seed) {
  const Section root = config::load(file);
  root.expect_only({"simulation", "guards", "domain", "materials", "pair", "sphere", "sphere_file", "sphere_group",
                    "clump", "stone_group", "state_file", "wall"});
  Scene scene;
  scene.source = file;
  read_simulation(root.section("simulation"), scene);
  if (seed) scene.seed = *seed;
  if (auto guards = root.optional_section("guards")) read_guards(*guards, scene.settings.guards);
  read_domain(root.section("domain"), scene.domain);

  const Section materials = root.section("materials");
  const auto names = materials.names();
  if (names.empty()) materials.fail("", "at least one material, e.g. [materials.ballast]");
  for (const auto& name : names) scene.materials.add(read_material(materials.section(name), name));
  for (const auto& pair : root.sections("pair")) scene.materials.add_override(read_pair_override(pair, names));

  for (const auto& s : root.sections("sphere")) scene.spheres.push_back(read_sphere(s, scene.materials));
  for (const auto& s : root.sections("sphere_file")) {
    auto more = read_sphere_file(s, scene.materials);
    scene.spheres.insert(scene.spheres.end(), more.begin(), more.end());
  }
  std::uint64_t group_seed = scene.seed;
  for (const auto& s : root.sections("sphere_group")) {
    auto more = generate_sphere_group(s, scene.materials, group_seed++);
    scene.spheres.insert(scene.spheres.end(), more.begin(), more.end());
  }
  for (const auto& s : root.sections("clump")) scene.clumps.push_back(read_clump(s, scene.materials));
  std::int64_t first_stone = 0;
  for (const auto& s : root.sections("stone_group")) {
    auto stones = generate_stone_group(s, scene.materials, scene.seed, first_stone);
    first_stone += static_cast<std::int64_t>(stones.clumps.size() + stones.balls.size());
    scene.clumps.insert(scene.clumps.end(), stones.clumps.begin(), stones.clumps.end());
    scene.spheres.insert(scene.spheres.end(), stones.balls.begin(), stones.balls.end());
  }
  for (const auto& s : root.sections("state_file")) read_state_file(s, scene);
  int wall_index = 0;
  for (const auto& s : root.sections("wall")) read_walls(s, wall_index++, scene);
  root.finish();
  if (scene.spheres.empty() && scene.clumps.empty())
    throw config::ConfigError(file.string() + ": the scene places no bodies; add [[sphere]], "
                              "[[sphere_file]], [[sphere_group]], [[clump]], [[stone_group]] or [[state_file]]");
  return scene;
}

dem::Simulation make_simulation(const Scene& scene) {
  dem::Simulation sim(scene.domain, scene.materials, scene.settings);
  for (const auto& s : scene.spheres) sim.add_sphere(s);
  for (const auto& c : scene.clumps) sim.add_clump(c);
  for (const auto& w : scene.walls) sim.add_wall(w);
  return sim;
}

}  // namespace mfdem::scene
