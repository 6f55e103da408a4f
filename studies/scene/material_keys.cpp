#include "studies/scene/material_keys.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace mfdem::scene {
namespace {

using config::Range;
const Range kPositive{.min = 0.0, .min_exclusive = true};
const Range kNonNegative{.min = 0.0};
const Range kFraction{.min = 0.0, .max = 1.0};
// Beyond these no granular material lies, and the products the time step and the series
// stiffness take of them would overflow (kn = 1e300 gave a limit of 0 s with kn = inf).
const Range kStiffness{.min = 0.0, .max = 1e15, .min_exclusive = true};
const Range kDensity{.min = 0.0, .max = 1e5, .min_exclusive = true};

}  // namespace

dem::Material read_material(const config::Section& s, const std::string& name) {
  dem::Material m;
  m.name = name;
  m.density = s.number("density", kDensity, "density in kg/m^3");
  m.normal_stiffness = s.number("normal_stiffness", kStiffness, "normal stiffness kn in N/m");
  m.shear_stiffness = s.number("shear_stiffness", kStiffness, "shear stiffness ks in N/m");
  m.friction = s.number("friction", kNonNegative, "friction coefficient");
  m.rolling_friction = s.number_or("rolling_friction", 0.0, kNonNegative,
                                   "rolling friction coefficient mu_r");
  m.damping_ratio = s.number_or("damping_ratio", 0.0, kFraction,
                                "viscous damping ratio (fraction of critical)");
  m.local_damping = s.number_or("local_damping", 0.0, {.min = 0.0, .max = 1.0, .max_exclusive = true},
                                "local damping coefficient alpha");
  return m;
}

dem::PairOverride read_pair_override(const config::Section& s, const std::vector<std::string>& known) {
  const auto names = s.strings_or("materials", {});
  if (names.size() != 2) s.fail("materials", "two material names, e.g. [\"ballast\", \"sleeper\"]");
  for (const auto& n : names)
    if (std::find(known.begin(), known.end(), n) == known.end())
      s.fail("materials", fmt::format("names of defined materials ({})", fmt::join(known, ", ")));
  dem::PairOverride o;
  o.material_a = names[0];
  o.material_b = names[1];
  if (s.has("friction")) o.friction = s.number("friction", kNonNegative, "friction coefficient");
  if (s.has("rolling_friction"))
    o.rolling_friction = s.number("rolling_friction", kNonNegative, "rolling friction coefficient mu_r");
  if (s.has("damping_ratio"))
    o.damping_ratio = s.number("damping_ratio", kFraction, "viscous damping ratio");
  return o;
}

void read_guards(const config::Section& s, dem::GuardSettings& g) {
  g.max_overlap_fraction = s.number_or("max_overlap_fraction", g.max_overlap_fraction,
                                       {.min = 0.0, .max = 1.0, .min_exclusive = true},
                                       "largest overlap as a fraction of the radius");
  g.check_interval = static_cast<int>(s.integer_or("check_interval", g.check_interval, {.min = 1},
                                                   "steps between energy checks"));
  g.energy_growth = s.number_or("energy_growth", g.energy_growth, kPositive,
                                "allowed energy growth as a fraction of the energy scale");
}

}  // namespace mfdem::scene
