#include "studies/railway/section_geometry.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace mfdem::railway {

double SectionGeometry::surface_height(double x) const {
  const double beyond_crest = std::abs(x) - crest_half_width();
  if (beyond_crest <= 0.0) return ballast_top();
  return std::max(0.0, ballast_top() - beyond_crest / shoulder_slope);
}

bool SectionGeometry::inside_sleeper(double x, double y, double z) const {
  return std::abs(x) <= 0.5 * sleeper_length && std::abs(y - 0.5 * section_length) <= 0.5 * sleeper_width &&
         z >= sleeper_base() && z <= ballast_top();
}

bool SectionGeometry::inside_ballast(double x, double z) const {
  return z >= 0.0 && z <= surface_height(x);
}

void validate(const SectionGeometry& g, double largest_stone) {
  auto need = [](bool ok, const char* key, const std::string& what) {
    if (!ok) throw GeometryError(key, what);
  };
  const std::pair<const char*, double> positive[] = {
      {"sleeper_length", g.sleeper_length}, {"sleeper_width", g.sleeper_width},
      {"sleeper_height", g.sleeper_height}, {"sleeper_mass", g.sleeper_mass},
      {"section_length", g.section_length}, {"depth_under_sleeper", g.depth_under_sleeper},
      {"shoulder_slope", g.shoulder_slope}};
  for (const auto& [name, value] : positive)
    need(std::isfinite(value) && value > 0.0, name, fmt::format("{} = {} m: must be > 0", name, value));
  need(std::isfinite(g.shoulder_width) && g.shoulder_width >= 0.0, "shoulder_width",
       fmt::format("shoulder_width = {} m: must be >= 0", g.shoulder_width));
  need(g.shoulder_width == 0.0 || g.shoulder_width >= largest_stone, "shoulder_width",
       fmt::format("shoulder_width = {} m: a shoulder must be at least one stone ({} m) wide, or 0",
                   g.shoulder_width, largest_stone));
  need(g.sleeper_width <= g.section_length, "sleeper_width",
       fmt::format("sleeper_width = {} m: the sleeper must fit in the section (section_length = {} m)",
                   g.sleeper_width, g.section_length));
  need(g.depth_under_sleeper >= 2.0 * largest_stone, "depth_under_sleeper",
       fmt::format("depth_under_sleeper = {} m: at least two stones ({} m) are needed under the sleeper",
                   g.depth_under_sleeper, 2.0 * largest_stone));
  if (g.periodic_along_track)
    need(g.section_length >= 3.0 * largest_stone, "section_length",
         fmt::format("section_length = {} m: a periodic section must be at least three stones ({} m) long",
                     g.section_length, 3.0 * largest_stone));
  need(g.section_length - g.sleeper_width >= largest_stone, "sleeper_width",
       fmt::format("sleeper_width = {} m: the crib between sleepers (section_length - sleeper_width = {} m) "
                   "must hold a stone ({} m)", g.sleeper_width, g.section_length - g.sleeper_width, largest_stone));
  // The crib is the sleeper's gap to its periodic image: the solver needs it wider than any
  // element (dem::Simulation::check_boxes_clear_periodic_faces), and the equal-volume ball of a
  // stone of size D is wider than D: 1.2 D leaves room for it.
  if (g.periodic_along_track)
    need(g.section_length - g.sleeper_width >= 1.2 * largest_stone, "sleeper_width",
         fmt::format("sleeper_width = {} m: with periodic ends the crib (section_length - sleeper_width = {} m) "
                     "must be at least 1.2 stones ({} m) wide", g.sleeper_width,
                     g.section_length - g.sleeper_width, 1.2 * largest_stone));
}

}  // namespace mfdem::railway
