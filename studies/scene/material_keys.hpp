#pragma once
// Keys shared by every config that defines materials or guards: scene files and the railway
// study configs.
#include <string>
#include <vector>

#include "dem/material.hpp"
#include "dem/stability.hpp"
#include "studies/config/config.hpp"

namespace mfdem::scene {

// [materials.NAME]: density, normal_stiffness, shear_stiffness, friction (required);
// rolling_friction, damping_ratio, local_damping (default 0).
dem::Material read_material(const config::Section& s, const std::string& name);

// [[pair]]: materials = ["a", "b"] (two of `known`) and any of friction, rolling_friction,
// damping_ratio, which replace the mixed value for that pair.
dem::PairOverride read_pair_override(const config::Section& s, const std::vector<std::string>& known);

// [guards]: max_overlap_fraction, check_interval, energy_growth (defaults of GuardSettings).
void read_guards(const config::Section& s, dem::GuardSettings& g);

}  // namespace mfdem::scene
