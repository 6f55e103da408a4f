#include "dem/material.hpp"

#include <algorithm>
#include <stdexcept>

namespace mfdem::dem {

double series_stiffness(double ka, double kb) { return ka * kb / (ka + kb); }

int MaterialTable::add(const Material& material) {
  if (index_of(material.name) >= 0)
    throw std::invalid_argument("material '" + material.name + "' is defined twice");
  materials_.push_back(material);
  remix();
  return size() - 1;
}

void MaterialTable::add_override(const PairOverride& override_values) {
  for (const auto& name : {override_values.material_a, override_values.material_b})
    if (index_of(name) < 0)
      throw std::invalid_argument("pair override names unknown material '" + name + "'");
  overrides_.push_back(override_values);
  remix();
}

int MaterialTable::index_of(const std::string& name) const {
  for (int i = 0; i < size(); ++i)
    if (materials_[i].name == name) return i;
  return -1;
}

void MaterialTable::remix() {
  const int n = size();
  pairs_.assign(static_cast<std::size_t>(n) * n, {});
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const Material& ma = materials_[a];
      const Material& mb = materials_[b];
      PairParameters p;
      p.normal_stiffness = series_stiffness(ma.normal_stiffness, mb.normal_stiffness);
      p.shear_stiffness = series_stiffness(ma.shear_stiffness, mb.shear_stiffness);
      // The weaker surface governs sliding, rolling and damping unless overridden.
      p.friction = std::min(ma.friction, mb.friction);
      p.rolling_friction = std::min(ma.rolling_friction, mb.rolling_friction);
      p.damping_ratio = std::min(ma.damping_ratio, mb.damping_ratio);
      for (const auto& o : overrides_) {
        const bool match = (o.material_a == ma.name && o.material_b == mb.name) ||
                           (o.material_a == mb.name && o.material_b == ma.name);
        if (!match) continue;
        if (o.friction) p.friction = *o.friction;
        if (o.rolling_friction) p.rolling_friction = *o.rolling_friction;
        if (o.damping_ratio) p.damping_ratio = *o.damping_ratio;
      }
      pairs_[a * n + b] = p;
    }
  }
}

}  // namespace mfdem::dem
