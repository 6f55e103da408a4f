#include "studies/campaigns/compare_figures.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <optional>
#include <cmath>
#include <stdexcept>

#include "dem/hdf5_io.hpp"
#include "studies/campaigns/paired_statistics.hpp"
#include "studies/railway/push_test.hpp"

namespace mfdem::campaigns {
namespace {

namespace fs = std::filesystem;
namespace h5 = dem::h5;

// An HDF5 file opened for reading, closed on every path out.
struct ReadFile {
  hid_t id = -1;
  explicit ReadFile(const fs::path& path) {
    H5E_BEGIN_TRY { id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT); }
    H5E_END_TRY;
    if (id < 0) throw std::runtime_error(fmt::format("{}: cannot open it as an HDF5 file", path.string()));
  }
  ~ReadFile() { H5Fclose(id); }
  ReadFile(const ReadFile&) = delete;
  ReadFile& operator=(const ReadFile&) = delete;
};

// What one run leaves for its section view.
struct EndState {
  std::vector<dem::Vec3> position, displacement, contact_point, contact_force;
  std::vector<dem::Index> body_a, body_b;
  std::vector<double> size;                 // sieve size per stone, m
  dem::Vec3 sleeper_centre, sleeper_half;   // before the push, m
  double u_end = 0.0, heave_end = 0.0;      // m
  double domain_max_x = 0.0;                // m
};

EndState read_end_state(const RunFiles& run) {
  EndState s;
  {
    ReadFile file(run.push);
    if (H5Lexists(file.id, "end_state", H5P_DEFAULT) <= 0)
      throw std::runtime_error(fmt::format("{}: no /end_state (the push did not finish)", run.push.string()));
    s.position = h5::read_vec3s(file.id, "end_state/position");
    s.displacement = h5::read_vec3s(file.id, "end_state/displacement");
    s.contact_point = h5::read_vec3s(file.id, "end_state/contact_point");
    s.contact_force = h5::read_vec3s(file.id, "end_state/contact_force");
    s.body_a = h5::read_ints(file.id, "end_state/contact_body_a");
    s.body_b = h5::read_ints(file.id, "end_state/contact_body_b");
    const auto u = h5::read_doubles(file.id, "curve/u");
    const auto heave = h5::read_doubles(file.id, "curve/heave");
    s.u_end = u.empty() ? 0.0 : u.back();
    s.heave_end = heave.empty() ? 0.0 : heave.back();
  }
  ReadFile file(run.packing);
  const hid_t g = H5Gopen2(file.id, "packing", H5P_DEFAULT);
  if (g < 0) throw std::runtime_error(fmt::format("{}: no /packing group (not a packing.h5)", run.packing.string()));
  try {
    for (int k = 0; k < 3; ++k) {
      const char axis = "xyz"[k];
      s.sleeper_centre[k] = h5::read_attribute(g, fmt::format("sleeper_centre_{}", axis));
      s.sleeper_half[k] = h5::read_attribute(g, fmt::format("sleeper_half_extent_{}", axis));
    }
    s.domain_max_x = h5::read_attribute(g, "domain_max_x");
    s.size = h5::read_doubles(g, "size");
  } catch (...) {
    H5Gclose(g);
    throw;
  }
  H5Gclose(g);
  if (s.size.size() != s.position.size())
    throw std::runtime_error(fmt::format("{} holds {} stones, {} of the same run {}", run.packing.string(),
                                         s.size.size(), run.push.string(), s.position.size()));
  return s;
}

}  // namespace

CurveBand curve_band(const std::string& model, const std::vector<railway::ForceCurve>& curves, std::size_t points) {
  CurveBand band;
  band.model = model;
  band.seeds = curves.size();
  if (curves.empty() || points < 2) return band;
  double u_last = std::numeric_limits<double>::infinity();
  for (const auto& c : curves) u_last = std::min(u_last, c.u.empty() ? 0.0 : c.u.back());
  if (!(u_last > 0.0)) return band;
  for (std::size_t k = 0; k < points; ++k) {
    const double u = u_last * double(k) / double(points - 1);
    double sum = 0.0, low = std::numeric_limits<double>::infinity(), high = -low;
    for (const auto& c : curves) {
      const double f = interpolate_curve(c.u, c.force, u);
      sum += f;
      low = std::min(low, f);
      high = std::max(high, f);
    }
    band.u.push_back(u);
    band.mean.push_back(sum / double(curves.size()));
    band.low.push_back(low);
    band.high.push_back(high);
  }
  return band;
}

Sections section_views(std::uint64_t seed, const std::vector<RunFiles>& runs) {
  Sections sections;
  sections.seed = seed;
  std::vector<EndState> states;
  for (const auto& run : runs) states.push_back(read_end_state(run));
  if (states.empty()) return sections;

  const EndState& reference = states.front();
  double largest_size = 0.0;
  for (const auto& s : states)
    for (double d : s.size) largest_size = std::max(largest_size, d);
  sections.slab_half_width = 0.5 * largest_size;
  const dem::Vec3& c = reference.sleeper_centre;
  const dem::Vec3& half = reference.sleeper_half;
  sections.x_min = c.x() - half.x() - 0.1;
  // To the bed's toe: the reference's farthest stone ahead of the sleeper, with its size.
  sections.x_max = c.x() + half.x();
  for (std::size_t k = 0; k < reference.position.size(); ++k)
    sections.x_max = std::max(sections.x_max, reference.position[k].x() + 0.5 * reference.size[k]);
  sections.x_max = std::min(sections.x_max + 0.02, reference.domain_max_x);
  sections.z_min = 0.0;
  sections.z_max = c.z() + half.z() + 0.05;
  sections.sleeper_x0 = c.x() - half.x() + reference.u_end;
  sections.sleeper_x1 = c.x() + half.x() + reference.u_end;
  sections.sleeper_z0 = c.z() - half.z() + reference.heave_end;
  sections.sleeper_z1 = c.z() + half.z() + reference.heave_end;

  // The chains' threshold: the reference's mean stone-stone contact force over the whole bed.
  double sum = 0.0;
  for (const auto& f : reference.contact_force) sum += f.norm();
  sections.chain_threshold = reference.contact_force.empty() ? 0.0 : sum / double(reference.contact_force.size());

  const auto in_slab = [&](const dem::Vec3& p) { return std::abs(p.y() - c.y()) <= sections.slab_half_width; };
  const auto in_region = [&](const dem::Vec3& p) {
    return p.x() >= sections.x_min && p.x() <= sections.x_max && p.z() >= sections.z_min && p.z() <= sections.z_max;
  };
  std::vector<double> all_displacements, all_chains;
  for (std::size_t m = 0; m < states.size(); ++m) {
    const EndState& s = states[m];
    SectionView view;
    view.model = runs[m].model;
    for (std::size_t k = 0; k < s.position.size(); ++k) {
      const dem::Vec3& p = s.position[k];
      if (!in_slab(p) || !in_region(p)) continue;
      view.x.push_back(p.x());
      view.z.push_back(p.z());
      view.radius.push_back(0.5 * s.size[k]);
      view.displacement.push_back(s.displacement[k].norm());
      view.dx.push_back(s.displacement[k].x());
      view.dz.push_back(s.displacement[k].z());
      all_displacements.push_back(view.displacement.back());
    }
    for (std::size_t k = 0; k < s.contact_point.size(); ++k) {
      const double f = s.contact_force[k].norm();
      if (f < sections.chain_threshold || !in_slab(s.contact_point[k]) || !in_region(s.contact_point[k])) continue;
      const auto a = static_cast<std::size_t>(s.body_a[k]), b = static_cast<std::size_t>(s.body_b[k]);
      if (a >= s.position.size() || b >= s.position.size()) continue;
      view.x1.push_back(s.position[a].x());
      view.z1.push_back(s.position[a].z());
      view.x2.push_back(s.position[b].x());
      view.z2.push_back(s.position[b].z());
      view.force.push_back(f);
      all_chains.push_back(f);
      sections.largest_chain_force = std::max(sections.largest_chain_force, f);
    }
    sections.models.push_back(std::move(view));
  }
  sections.displacement_clip = railway::nearest_rank_quantile(all_displacements, sections.clip_percentile);
  sections.chain_clip = railway::nearest_rank_quantile(all_chains, sections.clip_percentile);
  return sections;
}

void write_figure_data(const fs::path& path, const FigureLabels& labels, const std::vector<CurveBand>& curves,
                       const Sections& sections) {
  h5::write_file(path, [&](hid_t file) {
    h5::write_attribute(file, "config", labels.config);
    h5::write_attribute(file, "seeds", double(labels.seeds));
    h5::write_attribute(file, "tolerance", labels.tolerance);
    for (std::size_t m = 0; m < curves.size(); ++m) {
      const hid_t g = h5::make_group(file, fmt::format("curves/{:02d}", m));
      h5::write_attribute(g, "model", curves[m].model);
      h5::write_attribute(g, "seeds", double(curves[m].seeds));
      h5::write_doubles(g, "u", curves[m].u);
      h5::write_doubles(g, "mean", curves[m].mean);
      h5::write_doubles(g, "low", curves[m].low);
      h5::write_doubles(g, "high", curves[m].high);
      H5Gclose(g);
    }
    const hid_t s = h5::make_group(file, "section");
    for (const auto& [name, value] :
         {std::pair{"seed", double(sections.seed)}, {"slab_half_width", sections.slab_half_width},
          {"x_min", sections.x_min}, {"x_max", sections.x_max}, {"z_min", sections.z_min}, {"z_max", sections.z_max},
          {"displacement_clip", sections.displacement_clip}, {"clip_percentile", sections.clip_percentile},
          {"chain_threshold", sections.chain_threshold}, {"largest_chain_force", sections.largest_chain_force}, {"chain_clip", sections.chain_clip},
          {"sleeper_x0", sections.sleeper_x0}, {"sleeper_x1", sections.sleeper_x1},
          {"sleeper_z0", sections.sleeper_z0}, {"sleeper_z1", sections.sleeper_z1}})
      h5::write_attribute(s, name, value);
    H5Gclose(s);
    for (std::size_t m = 0; m < sections.models.size(); ++m) {
      const SectionView& v = sections.models[m];
      const hid_t g = h5::make_group(file, fmt::format("section/{:02d}", m));
      h5::write_attribute(g, "model", v.model);
      for (const auto& [name, data] : {std::pair{"x", &v.x}, {"z", &v.z}, {"radius", &v.radius},
                                       {"displacement", &v.displacement}, {"dx", &v.dx}, {"dz", &v.dz},
                                       {"x1", &v.x1}, {"z1", &v.z1}, {"x2", &v.x2}, {"z2", &v.z2},
                                       {"force", &v.force}})
        h5::write_doubles(g, name, *data);
      H5Gclose(g);
    }
  });
}

bool write_compare_figure_data(const fs::path& path, const runs::RunStore& store, const CompareRequest& request) {
  const auto finished = [&](std::size_t m, std::uint64_t seed) -> std::optional<fs::path> {
    const auto record = store.find(run_key(request.config_of(m), request.models[m], seed));
    if (!record || !record->finished()) return std::nullopt;
    return store.run_folder(record->key);
  };
  std::optional<std::uint64_t> section_seed;
  for (std::uint64_t seed : request.seeds)
    if (!section_seed && finished(request.reference, seed)) section_seed = seed;
  if (!section_seed) return false;

  // The reference first: its curve band leads the F(u) plot, its section the stack.
  std::vector<std::size_t> order = {request.reference};
  for (std::size_t m = 0; m < request.models.size(); ++m)
    if (m != request.reference) order.push_back(m);
  std::vector<CurveBand> curves;
  std::vector<RunFiles> section_runs;
  for (std::size_t m : order) {
    const std::string name = request.label_of(m);
    std::vector<railway::ForceCurve> seed_curves;
    for (std::uint64_t seed : request.seeds)
      if (const auto folder = finished(m, seed)) seed_curves.push_back(railway::read_force_curve(*folder / "push.h5"));
    curves.push_back(curve_band(name, seed_curves));
    if (const auto folder = finished(m, *section_seed))
      section_runs.push_back({name, *folder / "push.h5", *folder / "packing.h5"});
  }
  write_figure_data(path, {request.config.name, request.seeds.size(), request.tolerance}, curves,
                    section_views(*section_seed, section_runs));
  return true;
}

void write_push_figure_data(const fs::path& path, const std::string& title, std::uint64_t seed,
                            const std::vector<RunFiles>& runs) {
  std::vector<CurveBand> curves;
  for (const auto& run : runs) curves.push_back(curve_band(run.model, {railway::read_force_curve(run.push)}));
  write_figure_data(path, {title, 1, 0.05}, curves, section_views(seed, runs));
}

}  // namespace mfdem::campaigns
