#include "studies/scene/sphere_sources.hpp"

#include <fmt/format.h>
#include <gsl/gsl_rng.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>

namespace mfdem::scene {
namespace {

dem::Vec3 to_vec(const std::array<double, 3>& a) { return dem::Vec3(a[0], a[1], a[2]); }

const config::Range kPositive{.min = 0.0, .min_exclusive = true};
// A sphere larger than this is no particle of any scene (1e300 passed, then every product overflowed).
const config::Range kRadius{.min = 0.0, .max = 1e3, .min_exclusive = true};

}  // namespace

std::vector<dem::Vec3> lattice_centres(const config::Section& s, const dem::Vec3& lo,
                                       const dem::Vec3& hi, double pitch, long long count,
                                       const char* what) {
  long long cells[3];
  for (int a = 0; a < 3; ++a) {
    cells[a] = static_cast<long long>(std::floor((hi[a] - lo[a]) / pitch));
    if (cells[a] < 1)
      s.fail("max", fmt::format("a region at least one of the {} ({:.4g} m) wide along {}", what,
                                pitch, "xyz"[a]));
  }
  if (count > cells[0] * cells[1] * cells[2])
    s.fail("count", fmt::format("at most {} {}, the lattice capacity of the region at pitch {:.4g} m",
                                cells[0] * cells[1] * cells[2], what, pitch));
  std::vector<dem::Vec3> centres;
  for (long long k = 0; k < count; ++k) {
    const long long ix = k % cells[0], iy = (k / cells[0]) % cells[1], iz = k / (cells[0] * cells[1]);
    centres.push_back(lo + dem::Vec3((ix + 0.5) * pitch, (iy + 0.5) * pitch, (iz + 0.5) * pitch));
  }
  return centres;
}

std::filesystem::path path_beside_scene(const config::Section& s, std::string_view key) {
  std::filesystem::path file = s.text(key);
  const std::string where = s.where(key);
  const auto colon = where.rfind(':');
  const std::filesystem::path scene_file = where.substr(0, colon == std::string::npos ? where.size() : colon);
  return file.is_relative() ? scene_file.parent_path() / file : file;
}

int material_key(const config::Section& s, const dem::MaterialTable& materials) {
  const std::string name = s.text("material");
  const int index = materials.index_of(name);
  if (index < 0) {
    std::string known;
    for (const auto& m : materials.all()) known += (known.empty() ? "" : ", ") + m.name;
    s.fail("material", "a material defined under [materials] (known: " + known + ")");
  }
  return index;
}

dem::SphereSpec read_sphere(const config::Section& s, const dem::MaterialTable& materials) {
  dem::SphereSpec sphere;
  sphere.position = to_vec(s.vec3("position", "sphere centre in m"));
  sphere.radius = s.number("radius", kRadius, "sphere radius in m");
  sphere.material = material_key(s, materials);
  sphere.velocity = to_vec(s.vec3_or("velocity", {0, 0, 0}, "velocity in m/s"));
  sphere.angular_velocity = to_vec(s.vec3_or("angular_velocity", {0, 0, 0}, "angular velocity in rad/s"));
  return sphere;
}

std::vector<dem::SphereSpec> read_sphere_file(const config::Section& s,
                                              const dem::MaterialTable& materials) {
  const std::filesystem::path file = path_beside_scene(s, "path");
  const int material = material_key(s, materials);
  const dem::Vec3 velocity = to_vec(s.vec3_or("velocity", {0, 0, 0}, "velocity in m/s"));
  std::ifstream in(file);
  if (!in) s.fail("path", fmt::format("a readable text file of spheres (cannot open {})", file.string()));
  std::vector<dem::SphereSpec> spheres;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    double v[4];
    int n = 0;
    while (n < 4 && fields >> v[n]) ++n;
    std::string extra;
    if (n == 0 && !(fields.clear(), fields >> extra)) continue;  // blank or comment line
    if (n != 4 || (fields >> extra) || !std::isfinite(v[0] + v[1] + v[2] + v[3]) || !(v[3] > 0))
      throw config::ConfigError(fmt::format(
          "{}:{}: expected 'x y z radius' (four finite numbers in m, radius > 0), got '{}' "
          "(sphere file named by {}.path at {})",
          file.string(), line_number, line, s.path(), s.where("path")));
    dem::SphereSpec sphere;
    sphere.position = dem::Vec3(v[0], v[1], v[2]);
    sphere.radius = v[3];
    sphere.material = material;
    sphere.velocity = velocity;
    spheres.push_back(sphere);
  }
  if (spheres.empty()) s.fail("path", fmt::format("a file with at least one sphere ({} has none)", file.string()));
  return spheres;
}

std::vector<dem::SphereSpec> generate_sphere_group(const config::Section& s,
                                                   const dem::MaterialTable& materials,
                                                   std::uint64_t seed) {
  const dem::Vec3 lo = to_vec(s.vec3("min", "region corner in m"));
  const dem::Vec3 hi = to_vec(s.vec3("max", "region corner in m"));
  const long long count = s.integer("count", {.min = 1}, "number of spheres");
  const double radius = s.number("radius", kRadius, "mean sphere radius in m");
  const double spread = s.number_or("radius_spread", 0.0, {.min = 0.0, .max = 1.0, .max_exclusive = true},
                                    "relative radius spread");
  const int material = material_key(s, materials);
  const dem::Vec3 velocity = to_vec(s.vec3_or("velocity", {0, 0, 0}, "velocity in m/s"));
  const double random_speed = s.number_or("random_speed", 0.0, {.min = 0.0}, "random speed in m/s");
  const double pitch = 2.0 * radius * (1.0 + spread) * 1.02;  // 2 % gap: no initial overlap
  const auto centres = lattice_centres(s, lo, hi, pitch, count, "spheres");
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(seed));
  std::vector<dem::SphereSpec> spheres;
  for (long long k = 0; k < count; ++k) {
    dem::SphereSpec sphere;
    sphere.position = centres[k];
    sphere.radius = radius * (1.0 + spread * (2.0 * gsl_rng_uniform(rng.get()) - 1.0));
    sphere.material = material;
    dem::Vec3 jitter(gsl_rng_uniform(rng.get()) - 0.5, gsl_rng_uniform(rng.get()) - 0.5,
                     gsl_rng_uniform(rng.get()) - 0.5);
    sphere.velocity = velocity + 2.0 * random_speed * jitter;
    spheres.push_back(sphere);
  }
  return spheres;
}

}  // namespace mfdem::scene
