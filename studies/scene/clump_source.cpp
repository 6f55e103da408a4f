#include "studies/scene/clump_source.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "fidelity/mass_properties.hpp"
#include "fidelity/sphere_union.hpp"
#include "studies/scene/sphere_sources.hpp"

namespace mfdem::scene {
namespace {

dem::Vec3 to_vec(const std::array<double, 3>& a) { return dem::Vec3(a[0], a[1], a[2]); }

// As [[sphere]]: no particle of any scene is larger than a kilometre.
const config::Range kRadius{.min = 0.0, .max = 1e3, .min_exclusive = true};

std::vector<fidelity::Pebble> read_pebbles(const config::Section& s) {
  std::vector<fidelity::Pebble> pebbles;
  for (const auto& p : s.sections("pebble")) {
    pebbles.push_back({to_vec(p.vec3("offset", "pebble centre in the clump's frame, m")),
                       p.number("radius", kRadius, "pebble radius in m")});
  }
  if (pebbles.empty())
    s.fail("pebble", "at least one pebble, each a [[clump.pebble]] table with offset = [x, y, z] and radius");
  return pebbles;
}

dem::Quat read_rotation(const config::Section& s) {
  const dem::Vec3 axis = to_vec(s.vec3_or("axis", {0, 0, 1}, "rotation axis of the pebble frame"));
  const double angle = s.number_or("angle", 0.0, {}, "rotation angle about axis in rad");
  if (!(axis.norm() > 0.0)) s.fail("axis", "a non-zero vector");
  return dem::Quat(Eigen::AngleAxisd(angle, axis.normalized()));
}

}  // namespace

dem::ClumpSpec read_clump(const config::Section& s, const dem::MaterialTable& materials) {
  const dem::Vec3 origin = to_vec(s.vec3("position", "where the pebble frame's origin goes, m"));
  const dem::Quat rotation = read_rotation(s);
  const int material = material_key(s, materials);
  const auto pebbles = read_pebbles(s);
  const auto properties = fidelity::sphere_union_mass_properties(pebbles);
  if (!properties.converged)
    s.fail("pebble", fmt::format("pebbles whose union's mass properties converge (relative error {:.3g} after "
                                 "{} points)", properties.inertia_error, properties.points));
  const auto& union_solid = properties.properties;
  const auto principal = fidelity::principal_axes(union_solid.inertia);
  const double density = materials[material].density;

  dem::ClumpSpec c;
  c.material = material;
  c.mass = density * union_solid.volume;
  c.principal_inertia = density * principal.moments;
  // The solver keeps pebbles in the principal frame about the centre of mass.
  for (const auto& p : pebbles)
    c.pebbles.push_back({principal.axes.transpose() * (p.centre - union_solid.centroid), p.radius});
  c.orientation = (rotation * dem::Quat(principal.axes)).normalized();
  c.position = origin + rotation * union_solid.centroid;
  c.velocity = to_vec(s.vec3_or("velocity", {0, 0, 0}, "velocity of the centre of mass in m/s"));
  c.angular_velocity = to_vec(s.vec3_or("angular_velocity", {0, 0, 0}, "angular velocity in rad/s"));
  return c;
}

}  // namespace mfdem::scene
