#include "studies/railway/packing.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "dem/hdf5_io.hpp"
#include "dem/state_file.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/section_simulation.hpp"

namespace mfdem::railway {
namespace {

constexpr const char* kFormat = "mfdem-packing-1";

void write_vec3_attribute(hid_t loc, const std::string& name, const dem::Vec3& v) {
  for (int a = 0; a < 3; ++a) dem::h5::write_attribute(loc, name + "_" + "xyz"[a], v[a]);
}

dem::Vec3 read_vec3_attribute(hid_t loc, const std::string& name) {
  dem::Vec3 v;
  for (int a = 0; a < 3; ++a) v[a] = dem::h5::read_attribute(loc, name + "_" + "xyz"[a]);
  return v;
}

void write_springs(hid_t packing, const std::vector<dem::SpringState>& springs) {
  const hid_t g = dem::h5::make_group(packing, "springs");
  std::vector<dem::Index> kind, first, second;
  std::vector<dem::Vec3> shear, rolling;
  std::vector<double> damping;
  for (const auto& s : springs) {
    kind.push_back(static_cast<dem::Index>(s.kind));
    first.push_back(s.first);
    second.push_back(s.second);
    shear.push_back(s.history.shear_force);
    rolling.push_back(s.history.rolling_moment);
    damping.push_back(s.history.damping_force);
  }
  dem::h5::write_ints(g, "kind", kind);
  dem::h5::write_ints(g, "first", first);
  dem::h5::write_ints(g, "second", second);
  dem::h5::write_vec3s(g, "shear_force", shear);
  dem::h5::write_vec3s(g, "rolling_moment", rolling);
  dem::h5::write_doubles(g, "damping_force", damping);
  H5Gclose(g);
}

std::vector<dem::SpringState> read_springs(hid_t packing) {
  std::vector<dem::SpringState> springs;
  if (H5Lexists(packing, "springs", H5P_DEFAULT) <= 0) return springs;  // an older packing
  const hid_t g = H5Gopen2(packing, "springs", H5P_DEFAULT);
  const auto kind = dem::h5::read_ints(g, "kind");
  const auto first = dem::h5::read_ints(g, "first");
  const auto second = dem::h5::read_ints(g, "second");
  const auto shear = dem::h5::read_vec3s(g, "shear_force");
  const auto rolling = dem::h5::read_vec3s(g, "rolling_moment");
  const auto damping = dem::h5::read_doubles(g, "damping_force");
  H5Gclose(g);
  const std::size_t n = kind.size();
  if (first.size() != n || second.size() != n || shear.size() != n || rolling.size() != n || damping.size() != n)
    throw std::runtime_error(fmt::format("/packing/springs: datasets of different lengths (kind has {})", n));
  for (std::size_t k = 0; k < n; ++k) {
    if (kind[k] < 0 || kind[k] > 2)
      throw std::runtime_error(fmt::format("/packing/springs/kind[{}] = {}: expected 0, 1 or 2", k, kind[k]));
    springs.push_back({static_cast<dem::SpringState::Kind>(kind[k]), first[k], second[k],
                       dem::ContactHistory{shear[k], rolling[k], damping[k]}});
  }
  return springs;
}

}  // namespace

std::int64_t Packing::element_count() const {
  std::int64_t n = 0;
  for (const auto& b : bodies) n += static_cast<std::int64_t>(b.pebbles.size());
  return n;
}

std::vector<dem::ClumpSpec> body_states(const dem::Simulation& sim) {
  const dem::Bodies& bodies = sim.bodies();
  const dem::Elements& elements = sim.elements();
  std::vector<dem::ClumpSpec> out(bodies.size());
  for (dem::Index b = 0; b < bodies.size(); ++b) {
    dem::ClumpSpec& c = out[b];
    c.position = bodies.position[b];
    c.velocity = bodies.velocity[b];
    c.angular_velocity = bodies.angular_velocity[b];
    c.orientation = bodies.orientation[b];
    c.mass = bodies.mass[b];
    c.principal_inertia = bodies.inertia[b];
    for (dem::Index e = bodies.element_begin(b); e < bodies.element_end(b); ++e) {
      c.pebbles.push_back({elements.offset[e], elements.radius[e]});
      c.material = elements.material[e];
    }
  }
  return out;
}

void save_packing(const std::filesystem::path& path, const Packing& p) {
  StageSetup setup;
  setup.sleeper = p.sleeper;
  save_packing(path, p, setup, "prepared ballast bed");
}

void save_packing(const std::filesystem::path& path, const Packing& p, const StageSetup& setup,
                  const std::string& what) {
  // The sleeper is the packing's, where the bed has it; `setup` gives the other boundaries. (A
  // checkpoint once evaluated its frame with the sleeper at its design place: one that sank in the
  // consolidation then overlapped the clump that followed it down, and the writing failed.)
  StageSetup boundaries = setup;
  if (boundaries.sleeper) boundaries.sleeper = p.sleeper;
  dem::Simulation sim = make_section_simulation(p.config, p.domain, p.bodies, boundaries);
  sim.set_initial_springs(p.springs);
  sim.prepare();  // evaluates the contact forces the frame holds; the bodies do not move
  {
    dem::StateFile file(path, sim, fmt::format("{}, {} (seed {})", what, p.config.name, p.config.seed));
    file.write_frame(sim);
  }
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot reopen " + path.string());
  const hid_t g = dem::h5::make_group(file, "packing");
  using dem::h5::write_attribute;
  write_attribute(g, "format", std::string(kFormat));
  write_attribute(g, "seed", static_cast<double>(p.config.seed));
  write_attribute(g, "config", p.config.text);
  write_attribute(g, "config_source", p.config.source.string());
  write_attribute(g, "preparation_time", p.preparation_time);
  write_attribute(g, "unbalanced_force_ratio", p.unbalanced_force_ratio);
  write_vec3_attribute(g, "domain_min", p.domain.min);
  write_vec3_attribute(g, "domain_max", p.domain.max);
  write_attribute(g, "periodic_y", p.domain.periodic[1] ? 1.0 : 0.0);
  write_vec3_attribute(g, "sleeper_centre", p.sleeper.centre);
  write_vec3_attribute(g, "sleeper_half_extent", p.sleeper.half_extent);
  write_attribute(g, "sleeper_mass", p.sleeper.mass);
  if (!p.continued_from.empty()) write_attribute(g, "continued_from", p.continued_from);
  if (!p.model.empty()) {
    write_attribute(g, "model", p.model);
    // The balls' material as made (command-line choices are not in the config text).
    write_attribute(g, "model_rolling_friction", p.config.fidelity.rolling_friction);
    write_attribute(g, "model_ball_friction", p.config.fidelity.ball_friction.value_or(p.config.ballast.friction));
  }
  if (!p.conversion_point.empty()) write_attribute(g, "conversion_point", p.conversion_point);
  std::vector<dem::Index> ids, templates;
  std::vector<double> sizes;
  for (const auto& s : p.stones) {
    ids.push_back(static_cast<dem::Index>(s.id));
    templates.push_back(s.template_index);
    sizes.push_back(s.size);
  }
  dem::h5::write_ints(g, "stone_id", ids);
  dem::h5::write_ints(g, "template", templates);
  dem::h5::write_doubles(g, "size", sizes);
  write_springs(g, p.springs);
  H5Gclose(g);
  H5Fclose(file);
}

std::filesystem::path partial_path(const std::filesystem::path& path) {
  std::filesystem::path partial = path;
  return partial.replace_extension(".partial.h5");
}

void save_finished_packing(const std::filesystem::path& path, const Packing& p, const std::vector<StageReport>& stages) {
  const std::filesystem::path partial = partial_path(path);
  save_packing(partial, p);
  append_stage_reports(partial, stages);
  std::filesystem::rename(partial, path);
  std::filesystem::remove(std::filesystem::path(partial).replace_extension(".xdmf"));
  dem::write_xdmf_companion(path);
}

void append_stage_reports(const std::filesystem::path& path, const std::vector<StageReport>& stages) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot reopen " + path.string());
  const hid_t all = dem::h5::make_group(file, "packing/stages");
  for (std::size_t k = 0; k < stages.size(); ++k) {
    const StageReport& s = stages[k];
    const hid_t g = dem::h5::make_group(all, s.name.c_str());
    dem::h5::write_attribute(g, "simulated_time", s.simulated_time);
    dem::h5::write_attribute(g, "steps", static_cast<double>(s.steps));
    dem::h5::write_attribute(g, "settled", s.settled ? 1.0 : 0.0);
    dem::h5::write_attribute(g, "wall_seconds", s.wall_seconds);
    dem::h5::write_attribute(g, "end_unbalanced_force_ratio", s.unbalanced_force_ratio);
    dem::h5::write_attribute(g, "order", static_cast<double>(k));
    if (s.sleeper_base) dem::h5::write_attribute(g, "sleeper_base", *s.sleeper_base);
    if (s.sleeper_base_start) dem::h5::write_attribute(g, "sleeper_base_start", *s.sleeper_base_start);
    dem::h5::write_doubles(g, "time", s.check_time);
    dem::h5::write_doubles(g, "unbalanced_force_ratio", s.check_force_ratio);
    dem::h5::write_doubles(g, "kinetic_ratio", s.check_kinetic_ratio);
    if (!s.check_sleeper_base.empty()) dem::h5::write_doubles(g, "sleeper_base", s.check_sleeper_base);
    if (!s.check_creep.empty()) dem::h5::write_doubles(g, "creep", s.check_creep);
    if (s.settled_by_creep) dem::h5::write_attribute(g, "settled_by_creep", 1.0);
    H5Gclose(g);
  }
  H5Gclose(all);
  H5Fclose(file);
}

std::vector<StageReport> read_stage_reports(const std::filesystem::path& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error(fmt::format("{}: cannot open it as an HDF5 file", path.string()));
  std::vector<std::pair<double, StageReport>> ordered;
  if (H5Lexists(file, "packing", H5P_DEFAULT) > 0 && H5Lexists(file, "packing/stages", H5P_DEFAULT) > 0) {
    const hid_t all = H5Gopen2(file, "packing/stages", H5P_DEFAULT);
    H5G_info_t info;
    H5Gget_info(all, &info);
    for (hsize_t k = 0; k < info.nlinks; ++k) {
      std::string name(H5Lget_name_by_idx(all, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT), '\0');
      H5Lget_name_by_idx(all, ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size() + 1, H5P_DEFAULT);
      const hid_t g = H5Gopen2(all, name.c_str(), H5P_DEFAULT);
      using dem::h5::read_attribute;
      const auto has = [g](const char* key) { return H5Aexists(g, key) > 0; };
      StageReport s;
      s.name = name;
      s.simulated_time = read_attribute(g, "simulated_time");
      s.steps = static_cast<std::int64_t>(read_attribute(g, "steps"));
      s.settled = read_attribute(g, "settled") != 0.0;
      s.wall_seconds = read_attribute(g, "wall_seconds");
      if (has("sleeper_base")) s.sleeper_base = read_attribute(g, "sleeper_base");
      if (has("sleeper_base_start")) s.sleeper_base_start = read_attribute(g, "sleeper_base_start");
      s.check_time = dem::h5::read_doubles(g, "time");
      s.check_force_ratio = dem::h5::read_doubles(g, "unbalanced_force_ratio");
      s.check_kinetic_ratio = dem::h5::read_doubles(g, "kinetic_ratio");
      if (H5Lexists(g, "sleeper_base", H5P_DEFAULT) > 0) s.check_sleeper_base = dem::h5::read_doubles(g, "sleeper_base");
      if (H5Lexists(g, "creep", H5P_DEFAULT) > 0) s.check_creep = dem::h5::read_doubles(g, "creep");
      s.settled_by_creep = has("settled_by_creep") && read_attribute(g, "settled_by_creep") != 0.0;
      s.unbalanced_force_ratio = has("end_unbalanced_force_ratio") ? read_attribute(g, "end_unbalanced_force_ratio")
                                 : s.check_force_ratio.empty() ? 0.0 : s.check_force_ratio.back();
      // The stages ran in `order`; files from before it was written list them by name.
      const double order = has("order") ? read_attribute(g, "order") : static_cast<double>(k);
      H5Gclose(g);
      ordered.emplace_back(order, std::move(s));
    }
    H5Gclose(all);
  }
  H5Fclose(file);
  std::stable_sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<StageReport> stages;
  for (auto& [order, s] : ordered) stages.push_back(std::move(s));
  return stages;
}

std::optional<std::string> checkpoint_stage(const std::filesystem::path& path) {
  hid_t file = -1;
  H5E_BEGIN_TRY { file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT); }
  H5E_END_TRY;
  if (file < 0) return std::nullopt;
  std::optional<std::string> stage;
  if (H5Lexists(file, "packing", H5P_DEFAULT) > 0) {
    const hid_t g = H5Gopen2(file, "packing", H5P_DEFAULT);
    if (H5Aexists(g, "next_stage") > 0) stage = dem::h5::read_text_attribute(g, "next_stage");
    H5Gclose(g);
  }
  H5Fclose(file);
  return stage;
}

Packing load_packing(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path))
    throw std::runtime_error(fmt::format("{}: no such file (expected a packing.h5 written by `mfdem pack`, "
                                         "or the directory holding it)", path.string()));
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error(fmt::format("{}: cannot open it as an HDF5 file", path.string()));
  Packing p;
  try {
    if (H5Lexists(file, "packing", H5P_DEFAULT) <= 0)
      throw std::runtime_error("no /packing group: not a packing written by `mfdem pack`");
    const hid_t g = H5Gopen2(file, "packing", H5P_DEFAULT);
    using dem::h5::read_attribute;
    const std::string format = dem::h5::read_text_attribute(g, "format");
    if (format != kFormat) throw std::runtime_error(fmt::format("format '{}', expected '{}'", format, kFormat));
    p.config = parse_push_config(dem::h5::read_text_attribute(g, "config"),
                                 dem::h5::read_text_attribute(g, "config_source"));
    p.config.seed = static_cast<std::uint64_t>(read_attribute(g, "seed"));
    p.preparation_time = read_attribute(g, "preparation_time");
    p.unbalanced_force_ratio = read_attribute(g, "unbalanced_force_ratio");
    p.domain.min = read_vec3_attribute(g, "domain_min");
    p.domain.max = read_vec3_attribute(g, "domain_max");
    p.domain.periodic = {false, read_attribute(g, "periodic_y") != 0.0, false};
    p.sleeper.name = "sleeper";
    p.sleeper.centre = read_vec3_attribute(g, "sleeper_centre");
    p.sleeper.half_extent = read_vec3_attribute(g, "sleeper_half_extent");
    p.sleeper.mass = read_attribute(g, "sleeper_mass");
    p.continued_from = dem::h5::read_text_attribute(g, "continued_from");
    p.model = dem::h5::read_text_attribute(g, "model");
    if (H5Aexists(g, "model_rolling_friction") > 0) {  // packings of a model made before them lack them
      p.config.fidelity.rolling_friction = read_attribute(g, "model_rolling_friction");
      p.config.fidelity.ball_friction = read_attribute(g, "model_ball_friction");
    }
    p.conversion_point = dem::h5::read_text_attribute(g, "conversion_point");
    p.sleeper.material = kSleeper;
    p.sleeper.driven = {true, true, false};
    const auto ids = dem::h5::read_ints(g, "stone_id");
    const auto templates = dem::h5::read_ints(g, "template");
    const auto sizes = dem::h5::read_doubles(g, "size");
    for (std::size_t k = 0; k < ids.size(); ++k) p.stones.push_back({ids[k], static_cast<int>(templates[k]), sizes[k]});
    p.springs = read_springs(g);
    H5Gclose(g);
  } catch (const std::exception& e) {
    H5Fclose(file);
    throw std::runtime_error(fmt::format("{}: {}", path.string(), e.what()));
  }
  H5Fclose(file);
  const int frames = dem::count_frames(path);
  const dem::StateFrame frame = dem::read_frame(path, frames - 1);
  try {
    dem::require_valid_frame(frame);
  } catch (const std::invalid_argument& e) {
    // The file is the user's input: exit status 2, as for a config that names a wrong value.
    throw config::ConfigError(fmt::format("{}: expected a packing with {}", path.string(), e.what()));
  }
  // The packing's materials are ballast, sleeper, floor (and ball) in that order (section_simulation.hpp).
  std::vector<int> material_of;
  for (const auto& name : frame.material_names)
    material_of.push_back(name == "ballast" ? kBallast : name == "sleeper" ? kSleeper : name == "ball" ? kBall : kFloor);
  p.bodies = dem::bodies_of(frame, material_of);
  if (p.bodies.size() != p.stones.size())
    throw std::runtime_error(fmt::format("{}: {} bodies but {} stone records", path.string(),
                                         p.bodies.size(), p.stones.size()));
  return p;
}

}  // namespace mfdem::railway
