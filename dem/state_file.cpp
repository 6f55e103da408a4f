#include "dem/state_file.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include "dem/hdf5_io.hpp"

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace mfdem::dem {
using namespace h5;
namespace {

std::string frame_name(int frame) { return fmt::format("frames/{:06d}", frame); }

// PATH.xdmf for the frames of PATH: ParaView reads the element positions, radii, bodies and
// velocities of every frame from the HDF5 file, named relative to the XDMF file. The file is a
// header, one Grid per frame and a footer, so a frame is appended by overwriting the footer.
constexpr const char* kXdmfHeader =
    "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
    "<Grid Name=\"elements\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
constexpr const char* kXdmfFooter = "</Grid>\n</Domain>\n</Xdmf>\n";

std::filesystem::path xdmf_path(const std::filesystem::path& path) {
  std::filesystem::path xdmf = path;
  return xdmf.replace_extension(".xdmf");
}

std::string xdmf_frame(std::size_t f, double time, long long elements, const std::string& h5) {
  const std::string frame = frame_name(static_cast<int>(f));
  return fmt::format("<Grid Name=\"frame{0}\" GridType=\"Uniform\">\n<Time Value=\"{1:.9g}\"/>\n"
                     "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{2}\"/>\n"
                     "<Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"{2} 3\" "
                     "Format=\"HDF\" Precision=\"8\">{3}:/{4}/element_position</DataItem></Geometry>\n"
                     "<Attribute Name=\"radius\" Center=\"Node\"><DataItem Dimensions=\"{2}\" "
                     "Format=\"HDF\" Precision=\"8\">{3}:/elements/radius</DataItem></Attribute>\n"
                     "<Attribute Name=\"body\" Center=\"Node\"><DataItem Dimensions=\"{2}\" "
                     "NumberType=\"Int\" Format=\"HDF\">{3}:/elements/body</DataItem></Attribute>\n"
                     "<Attribute Name=\"velocity\" Center=\"Node\" AttributeType=\"Vector\">"
                     "<DataItem Dimensions=\"{2} 3\" Format=\"HDF\" Precision=\"8\">{3}:/{4}/"
                     "element_velocity</DataItem></Attribute>\n</Grid>\n",
                     f, time, elements, h5, frame);
}

void write_xdmf_file(const std::filesystem::path& path, const std::vector<double>& frame_times, long long elements) {
  std::ofstream out(xdmf_path(path));
  const std::string h5 = path.filename().string();
  out << kXdmfHeader;
  for (std::size_t f = 0; f < frame_times.size(); ++f) out << xdmf_frame(f, frame_times[f], elements, h5);
  out << kXdmfFooter;
}

}  // namespace

StateFile::StateFile(const std::filesystem::path& path, const Simulation& sim, std::string note)
    : path_(path) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) throw std::runtime_error("cannot create HDF5 file " + path.string());
  bodies_ = sim.bodies().size();
  elements_ = sim.elements().size();
  walls_ = static_cast<long long>(sim.walls().size());
  write_attribute(file_, "format", std::string("mfdem-state-1"));
  write_attribute(file_, "time_step", sim.time_step());
  write_attribute(file_, "note", note);
  const hid_t el = make_group(file_, "elements");
  write_doubles(el, "radius", sim.elements().radius.data(), elements_, 0);
  write_ints(el, "body", sim.elements().body);
  std::vector<Index> material(sim.elements().material.begin(), sim.elements().material.end());
  write_ints(el, "material", material);
  write_vec3s(el, "offset", sim.elements().offset);
  H5Gclose(el);
  const hid_t bodies = make_group(file_, "bodies");
  write_doubles(bodies, "mass", sim.bodies().mass.data(), bodies_, 0);
  write_vec3s(bodies, "inertia", sim.bodies().inertia);
  H5Gclose(bodies);
  const hid_t mat = make_group(file_, "materials");
  std::vector<std::string> names;
  for (const auto& m : sim.materials().all()) names.push_back(m.name);
  write_attribute(mat, "names", names);
  H5Gclose(mat);
  const hid_t walls = make_group(file_, "walls");
  names.clear();
  for (const auto& w : sim.walls()) names.push_back(w.name);
  write_attribute(walls, "names", names);
  H5Gclose(walls);
  H5Gclose(make_group(file_, "frames"));
  H5Gclose(make_group(file_, "series"));
  H5Fflush(file_, H5F_SCOPE_GLOBAL);
}

StateFile::~StateFile() {
  if (file_ >= 0) H5Fclose(file_);
}

void StateFile::write_frame(const Simulation& sim) {
  Simulation::Snapshot now{sim.time(), sim.step_count(), sim.bodies().position,
                           sim.bodies().velocity, sim.bodies().angular_velocity,
                           sim.bodies().orientation};
  write_snapshot(sim, now, "");
}

void StateFile::write_snapshot(const Simulation& sim, const Simulation::Snapshot& s,
                               const std::string& label) {
  const hid_t g = make_group(file_, frame_name(frames_));
  write_attribute(g, "time", s.time);
  write_attribute(g, "step", static_cast<double>(s.step));
  if (!label.empty()) write_attribute(g, "label", label);
  write_vec3s(g, "position", s.position);
  write_vec3s(g, "velocity", s.velocity);
  write_vec3s(g, "angular_velocity", s.angular_velocity);
  const Bodies& bodies = sim.bodies();
  if (label.empty()) write_vec3s(g, "unbalanced_force", bodies.unbalanced_force);
  const Elements& elements = sim.elements();
  std::vector<double> quat(bodies.size() * 4);
  for (Index b = 0; b < bodies.size(); ++b) {
    const Quat& q = s.orientation.empty() ? bodies.orientation[b] : s.orientation[b];
    quat[4 * b] = q.w(), quat[4 * b + 1] = q.x(), quat[4 * b + 2] = q.y(), quat[4 * b + 3] = q.z();
  }
  write_doubles(g, "orientation", quat.data(), bodies.size(), 4);
  std::vector<Vec3> ep(elements.size()), ev(elements.size());
  for (Index e = 0; e < elements.size(); ++e) {
    const Index b = elements.body[e];
    const Vec3 arm = (s.orientation.empty() ? bodies.orientation[b] : s.orientation[b]) * elements.offset[e];
    ep[e] = s.position[b] + arm;
    ev[e] = s.velocity[b] + s.angular_velocity[b].cross(arm);
  }
  write_vec3s(g, "element_position", ep);
  write_vec3s(g, "element_velocity", ev);
  const auto contacts = sim.contacts();
  std::vector<Index> a, b;
  std::vector<Vec3> point, force;
  for (const auto& c : contacts) {
    a.push_back(c.body_a), b.push_back(c.body_b);
    point.push_back(c.point), force.push_back(c.force);
  }
  write_ints(g, "contact_body_a", a);
  write_ints(g, "contact_body_b", b);
  write_vec3s(g, "contact_point", point);
  write_vec3s(g, "contact_force", force);
  std::vector<Vec3> wall_force;
  for (int w = 0; w < static_cast<int>(walls_); ++w) wall_force.push_back(sim.wall_force(w));
  write_vec3s(g, "wall_force", wall_force);
  H5Gclose(g);
  ++frames_;
  frame_times_.push_back(s.time);
  append_series(sim, s.time);
  H5Fflush(file_, H5F_SCOPE_GLOBAL);
  append_xdmf_frame();
}

void StateFile::append_series(const Simulation& sim, double time) {
  const EnergyReport e = sim.energy();
  const std::pair<const char*, double> values[] = {
      {"series/time", time},
      {"series/kinetic_energy", e.kinetic()},
      {"series/gravitational_energy", e.gravitational},
      {"series/elastic_energy", e.elastic},
      {"series/dissipated_damping", e.dissipated_damping},
      {"series/dissipated_friction", e.dissipated_friction},
      {"series/dissipated_local", e.dissipated_local},
      {"series/work_by_walls", e.work_by_walls},
  };
  for (const auto& [name, value] : values) append_row(file_, name, &value, 0);
  if (walls_ > 0) {
    std::vector<double> row;
    for (int w = 0; w < static_cast<int>(walls_); ++w)
      for (int a = 0; a < 3; ++a) row.push_back(sim.wall_force(w)[a]);
    append_row(file_, "series/wall_force", row.data(), row.size());
  }
}

void StateFile::append_xdmf_frame() {
  // The new frame overwrites the footer, which follows it: O(frame) per frame, and the file is
  // whole after every frame (a run that stops keeps a readable XDMF).
  const std::size_t f = frame_times_.size() - 1;
  std::fstream out;
  if (f == 0) {
    out.open(xdmf_path(path_), std::ios::out | std::ios::trunc | std::ios::binary);
    out << kXdmfHeader;
  } else {
    out.open(xdmf_path(path_), std::ios::in | std::ios::out | std::ios::binary);
    out.seekp(static_cast<std::streamoff>(xdmf_footer_at_));
  }
  out << xdmf_frame(f, frame_times_[f], elements_, path_.filename().string());
  xdmf_footer_at_ = static_cast<std::uint64_t>(out.tellp());
  out << kXdmfFooter;
  if (!out) throw std::runtime_error("cannot write " + xdmf_path(path_).string());
}

void write_xdmf_companion(const std::filesystem::path& path) {
  const int frames = count_frames(path);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot open HDF5 file " + path.string());
  std::vector<double> times;
  for (int f = 0; f < frames; ++f) {
    const hid_t g = H5Gopen2(file, frame_name(f).c_str(), H5P_DEFAULT);
    times.push_back(read_attribute(g, "time"));
    H5Gclose(g);
  }
  const auto elements = static_cast<long long>(read_doubles(file, "elements/radius").size());
  H5Fclose(file);
  write_xdmf_file(path, times, elements);
}

void require_valid_frame(const StateFrame& f) {
  const auto finite = [](const Vec3& v) { return v.allFinite(); };
  const auto positive = [](double x) { return x > 0.0 && std::isfinite(x); };
  for (std::size_t b = 0; b < f.position.size(); ++b) {
    if (!finite(f.position[b]) || !finite(f.velocity[b]) || !finite(f.angular_velocity[b]) ||
        !f.orientation[b].coeffs().allFinite())
      throw std::invalid_argument(fmt::format(
          "finite positions, velocities and orientations (frame at t = {:.6g} s: body {} has position {:.6g}, {:.6g}, "
          "{:.6g} m, velocity {:.6g}, {:.6g}, {:.6g} m/s, angular velocity {:.6g}, {:.6g}, {:.6g} rad/s)",
          f.time, b, f.position[b].x(), f.position[b].y(), f.position[b].z(), f.velocity[b].x(), f.velocity[b].y(),
          f.velocity[b].z(), f.angular_velocity[b].x(), f.angular_velocity[b].y(), f.angular_velocity[b].z()));
    if (!positive(f.mass[b]) || !positive(f.inertia[b].minCoeff()) || !finite(f.inertia[b]))
      throw std::invalid_argument(fmt::format(
          "a positive, finite mass and inertia of every body (body {} has mass {:.6g} kg, inertia {:.6g}, {:.6g}, "
          "{:.6g} kg m^2)",
          b, f.mass[b], f.inertia[b].x(), f.inertia[b].y(), f.inertia[b].z()));
  }
  for (std::size_t e = 0; e < f.element_radius.size(); ++e)
    if (!positive(f.element_radius[e]) || !finite(f.element_offset[e]))
      throw std::invalid_argument(fmt::format(
          "a positive, finite radius and offset of every element (element {} of body {} has radius {:.6g} m, "
          "offset {:.6g}, {:.6g}, {:.6g} m)",
          e, f.element_body[e], f.element_radius[e], f.element_offset[e].x(), f.element_offset[e].y(),
          f.element_offset[e].z()));
}

std::vector<ClumpSpec> bodies_of(const StateFrame& f, const std::vector<int>& material_of) {
  std::vector<ClumpSpec> out(f.position.size());
  for (std::size_t b = 0; b < out.size(); ++b) {
    out[b].position = f.position[b];
    out[b].velocity = f.velocity[b];
    out[b].angular_velocity = f.angular_velocity[b];
    out[b].orientation = f.orientation[b];
    out[b].mass = f.mass[b];
    out[b].principal_inertia = f.inertia[b];
  }
  for (std::size_t e = 0; e < f.element_body.size(); ++e) {
    ClumpSpec& c = out[f.element_body[e]];
    c.pebbles.push_back({f.element_offset[e], f.element_radius[e]});
    c.material = material_of[f.element_material[e]];
  }
  return out;
}

int count_frames(const std::filesystem::path& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot open HDF5 file " + path.string());
  int n = 0;
  if (H5Lexists(file, "frames", H5P_DEFAULT) <= 0) {
    H5Fclose(file);
    throw std::runtime_error(path.string() + " is not an mfdem state file (no /frames)");
  }
  while (H5Lexists(file, frame_name(n).c_str(), H5P_DEFAULT) > 0) ++n;
  H5Fclose(file);
  return n;
}

StateFrame read_frame(const std::filesystem::path& path, int frame) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot open HDF5 file " + path.string());
  StateFrame f;
  const std::string g = frame_name(frame);
  const hid_t group = H5Gopen2(file, g.c_str(), H5P_DEFAULT);
  if (group < 0) {
    H5Fclose(file);
    throw std::runtime_error(fmt::format("{} has no frame {}", path.string(), frame));
  }
  f.time = read_attribute(group, "time");
  f.step = static_cast<long long>(read_attribute(group, "step"));
  f.label = read_text_attribute(group, "label");
  H5Gclose(group);
  f.position = read_vec3s(file, g + "/position");
  f.velocity = read_vec3s(file, g + "/velocity");
  f.angular_velocity = read_vec3s(file, g + "/angular_velocity");
  f.element_radius = read_doubles(file, "elements/radius");
  f.element_body = read_ints(file, "elements/body");
  f.element_material = read_ints(file, "elements/material");
  f.element_offset = read_vec3s(file, "elements/offset");
  f.mass = read_doubles(file, "bodies/mass");
  f.inertia = read_vec3s(file, "bodies/inertia");
  {
    const auto q = read_doubles(file, g + "/orientation");
    for (std::size_t b = 0; b + 3 < q.size(); b += 4) f.orientation.emplace_back(q[b], q[b + 1], q[b + 2], q[b + 3]);
  }
  {
    const hid_t materials = H5Gopen2(file, "materials", H5P_DEFAULT);
    std::string names = read_text_attribute(materials, "names");
    H5Gclose(materials);
    for (std::size_t start = 0; start <= names.size();) {
      const auto comma = names.find(',', start);
      f.material_names.push_back(names.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  f.contact_body_a = read_ints(file, g + "/contact_body_a");
  f.contact_body_b = read_ints(file, g + "/contact_body_b");
  f.contact_force = read_vec3s(file, g + "/contact_force");
  f.wall_force = read_vec3s(file, g + "/wall_force");
  H5Fclose(file);
  return f;
}

}  // namespace mfdem::dem
