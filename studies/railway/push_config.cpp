#include "studies/railway/push_config.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "studies/config/config.hpp"
#include "studies/railway/stone_columns.hpp"
#include "studies/scene/material_keys.hpp"

namespace mfdem::railway {
namespace {

using config::Range;
using config::Section;
const Range kPositive{.min = 0.0, .min_exclusive = true};
const Range kNonNegative{.min = 0.0};
const Range kBelowOne{.min = 0.0, .max = 1.0, .max_exclusive = true};

void read_section(const Section& s, SectionGeometry& g) {
  g.sleeper_length = s.number_or("sleeper_length", g.sleeper_length, kPositive, "sleeper length in m");
  g.sleeper_width = s.number_or("sleeper_width", g.sleeper_width, kPositive, "sleeper width in m");
  g.sleeper_height = s.number_or("sleeper_height", g.sleeper_height, kPositive, "sleeper height in m");
  g.sleeper_mass = s.number_or("sleeper_mass", g.sleeper_mass, kPositive, "sleeper mass in kg");
  g.section_length = s.number_or("section_length", g.section_length, kPositive,
                                 "sleeper spacing along the track in m");
  g.depth_under_sleeper = s.number_or("depth_under_sleeper", g.depth_under_sleeper, kPositive,
                                      "ballast depth under the sleeper in m");
  g.shoulder_width = s.number_or("shoulder_width", g.shoulder_width, kNonNegative,
                                 "shoulder width beyond the sleeper end in m");
  g.shoulder_slope = s.number_or("shoulder_slope", g.shoulder_slope, kPositive,
                                 "shoulder slope, horizontal per vertical (1.5 for 1:1.5)");
  g.periodic_along_track = s.choice("along_track", {"periodic", "walls"}, "periodic") == "periodic";
}

void read_stones(const Section& s, const std::filesystem::path& source, StoneSettings& t) {
  if (s.has("library")) {
    t.library = s.text("library");
    if (t.library.is_relative()) t.library = source.parent_path() / t.library;
  }
  t.representation = fidelity::representation_named(s.choice("representation", {"clump", "ball"}, "clump"));
  t.solid_fraction = s.number_or("solid_fraction", t.solid_fraction, {.min = 0.2, .max = 0.8},
                                 "expected solid fraction of the settled bed");
  t.overfill = s.number_or("overfill", t.overfill, {.min = 1.0, .max = 2.0},
                           "stones generated per stone expected in the profile");
  t.fixed_size = s.number_or("size", 0.0, kNonNegative, "fixed sieve size in m (0: EN 13450 grading)");
}

void read_preparation(const Section& s, PreparationSettings& p) {
  p.deposition_friction = s.number_or("deposition_friction", p.deposition_friction, kNonNegative,
                                      "stone friction coefficient while depositing");
  p.drop_speed = s.number_or("drop_speed", p.drop_speed, kNonNegative, "initial downward speed of the highest stone in m/s");
  p.deposition_local_damping = s.number_or("deposition_local_damping", p.deposition_local_damping, kBelowOne,
                                           "local damping alpha of the stones while depositing");
  p.local_damping = s.number_or("local_damping", p.local_damping, kBelowOne,
                                "local damping alpha of the stones while settling");
  p.deposition_ratio = s.number_or("deposition_ratio", p.deposition_ratio, kPositive,
                                   "kinetic energy / (M g d_mean) that ends the deposition");
  p.equilibrium_ratio = s.number_or("equilibrium_ratio", p.equilibrium_ratio, kPositive,
                                    "mean unbalanced force ratio (and kinetic energy / (M g d_mean)) that counts as settled");
  p.max_deposition_time = s.number_or("max_deposition_time", p.max_deposition_time, kPositive,
                                      "longest deposition in simulated s");
  p.max_settling_time = s.number_or("max_settling_time", p.max_settling_time, kPositive,
                                    "longest settling stage in simulated s");
  p.creep_ratio = s.number_or("creep_ratio", p.creep_ratio, kNonNegative,
                              "stones' mean displacement over creep_window / their mean size that counts as settled (0: off)");
  p.creep_window = s.number_or("creep_window", p.creep_window, kPositive,
                               "simulated s over which the creep of the stones is measured");
  p.tamping_depth = s.number_or("tamping_depth", p.tamping_depth, {.min = 0.0, .max = 0.05},
                                "depth in m the sleeper's sides and ends press into the bed as it grows to its size");
  p.tamping_time = s.number_or("tamping_time", p.tamping_time, kPositive,
                               "simulated s over which the sleeper grows to its size");
  p.tamping_sleeper_held = s.choice("tamping_sleeper_vertical", {"free", "held"}, "free") == "held";
  p.consolidation_gravity = s.number_or("consolidation_gravity", p.consolidation_gravity, {.min = 1.0, .max = 50.0},
                                        "factor on gravity while the bed consolidates (1 = no consolidation)");
  p.consolidation_time = s.number_or("consolidation_time", p.consolidation_time, kPositive,
                                     "simulated s of the consolidation under raised gravity");
  p.expansion_strain = s.number_or("expansion_strain", p.expansion_strain, {.min = 0.0, .max = 0.05},
                                   "linear strain the stones grow by once the sleeper is in place (0 = none)");
  p.expansion_steps = static_cast<int>(s.integer_or("expansion_steps", p.expansion_steps, {.min = 1, .max = 1000},
                                                    "equal growth factors of the expansion"));
  p.expansion_time = s.number_or("expansion_time", p.expansion_time, kPositive,
                                 "simulated s over which the stones grow");
  p.traffic_cycles = static_cast<int>(s.integer_or("traffic_cycles", p.traffic_cycles, {.min = 0, .max = 100000},
                                                   "load pulses on the sleeper after the compaction (0 = none)"));
  p.traffic_load = s.number_or("traffic_load", p.traffic_load, kPositive,
                               "peak downward load of a traffic pulse on the sleeper in N");
  p.traffic_period = s.number_or("traffic_period", p.traffic_period, kPositive,
                                 "simulated s of one traffic load pulse");
}

void read_push(const Section& s, PushSettings& p) {
  p.velocity = s.number_or("velocity", p.velocity, kPositive, "lateral sleeper velocity in m/s");
  p.distance = s.number_or("distance", p.distance, kPositive, "push distance u_end in m");
  p.record_interval = s.number_or("record_interval", p.record_interval, kPositive,
                                  "sleeper displacement between F(u) samples in m");
  p.ramp_distance = s.number_or("ramp_distance", p.ramp_distance, kNonNegative,
                                "sleeper displacement over which the push speeds up, in m");
  p.local_damping = s.number_or("local_damping", p.local_damping, kBelowOne,
                                "local damping alpha of the stones while pushing");
  p.network_samples = static_cast<int>(s.integer_or("network_samples", p.network_samples, {.min = 1},
                                                    "samples of the inertial number during the push"));
  p.sleeper_held_vertically = s.choice("sleeper_vertical", {"free", "held"}, "free") == "held";
  if (p.record_interval > p.distance) s.fail("record_interval", "at most the push distance");
}

void read_fidelity(const Section& s, const SectionGeometry& g, FidelitySettings& f) {
  f.policy = s.text_or("policy", f.policy);
  try {
    // Checked against the design depth to the sleeper base; a push checks it again against the
    // settled bed's.
    fidelity::PolicyRegistry::builtin().make(f.policy, {g.sleeper_base()});
  } catch (const fidelity::PolicyError& e) {
    s.fail("policy", e.what());
  }
  f.rolling_friction = s.number_or("rolling_friction", f.rolling_friction, kNonNegative,
                                   "rolling friction coefficient mu_r of the balls");
  if (s.has("ball_friction"))
    f.ball_friction = s.number("ball_friction", kNonNegative, "friction coefficient of the balls");
  f.growth_time = s.number_or("growth_time", f.growth_time, kPositive,
                              "simulated s over which the converted balls grow to size");
  if (s.has("growth_friction"))
    f.growth_friction = s.number("growth_friction", kNonNegative, "friction coefficient while the balls grow");
}

dem::Material table1_material(const std::string& name, double stiffness, double density) {
  dem::Material m;
  m.name = name;
  m.density = density;
  m.normal_stiffness = stiffness;
  m.shear_stiffness = stiffness;
  m.friction = 0.5;
  m.damping_ratio = 0.2;
  return m;
}

PushStudyConfig read(const Section& root, const std::string& text, const std::filesystem::path& source) {
  PushStudyConfig c;
  c.source = source;
  c.text = text;
  c.name = root.text_or("name", source.stem().string());
  c.seed = static_cast<std::uint64_t>(root.integer_or("seed", 1, {.min = 0}, "random seed"));
  c.time_step_safety = root.number_or("time_step_safety", c.time_step_safety,
                                      {.min = 0.0, .max = 1.0, .min_exclusive = true},
                                      "fraction of the critical time step");
  if (auto s = root.optional_section("section")) read_section(*s, c.geometry);
  if (auto s = root.optional_section("stones")) read_stones(*s, source, c.stones);
  if (auto s = root.optional_section("preparation")) read_preparation(*s, c.preparation);
  if (auto s = root.optional_section("push")) read_push(*s, c.push);
  if (auto s = root.optional_section("fidelity")) read_fidelity(*s, c.geometry, c.fidelity);
  if (auto s = root.optional_section("guards")) scene::read_guards(*s, c.guards);
  // Table 1 of the paper unless the config says otherwise. The sleeper's density sets nothing
  // (its mass is sleeper_mass); the floor is as stiff as the sleeper.
  // Table 1 gives no damping: 0.2 of critical on every contact (a pair takes the smaller ratio,
  // so the sleeper and floor need it too, or the sleeper rings on the bed undamped).
  c.ballast = table1_material("ballast", 2e7, 2800.0);
  c.sleeper = table1_material("sleeper", 5e9, 2400.0);
  c.floor = table1_material("floor", 5e9, 2400.0);
  if (auto m = root.optional_section("materials")) {
    for (const auto& name : m->names()) {
      if (name != "ballast" && name != "sleeper" && name != "floor")
        m->fail(name, "one of the materials ballast, sleeper, floor");
      const dem::Material read = scene::read_material(m->section(name), name);
      (name == "ballast" ? c.ballast : name == "sleeper" ? c.sleeper : c.floor) = read;
    }
  }
  for (const auto& s : root.sections("pair")) {
    const dem::PairOverride o = scene::read_pair_override(s, {"ballast", "sleeper", "floor", "ball"});
    // A material's pair with itself is the material's own value (and the deposition lowers the
    // ballast's friction, which an override would undo).
    if (o.material_a == o.material_b)
      s.fail("materials", "two different materials (set a material's own value under [materials." + o.material_a + "])");
    c.pairs.push_back(o);
  }
  root.finish();
  return c;
}

}  // namespace

std::filesystem::path preset_directory() { return MFDEM_PRESET_DIR; }

PushStudyConfig parse_push_config(const std::string& text, const std::filesystem::path& source) {
  return read(config::parse(text, source.string()), text, source);
}

PushStudyConfig load_push_config(const std::string& preset_or_file) {
  std::filesystem::path file = preset_or_file;
  if (!std::filesystem::exists(file)) {
    const auto preset = preset_directory() / (preset_or_file + ".toml");
    if (preset_or_file.find('/') != std::string::npos || !std::filesystem::exists(preset))
      throw std::runtime_error(fmt::format(
          "{}: no such file, and not a preset (the presets are mini, study, standard and paper, in {})",
          preset_or_file, preset_directory().string()));
    file = preset;
  }
  std::ifstream in(file);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const Section root = config::load(file);
  PushStudyConfig c = read(root, text, file);
  // A section that cannot be built is refused now, naming its key and line, not after the
  // stones are drawn (a packing stored with its config was checked when it was made).
  try {
    validate(c.geometry, StoneFactory(c).upper_size());
  } catch (const GeometryError& e) {
    const auto section = root.optional_section("section");
    const std::string where = section && section->has(e.key) ? section->where(e.key) : file.string();
    throw config::ConfigError(fmt::format("{}: [section] {}", where, e.what()));
  }
  return c;
}

}  // namespace mfdem::railway
