#pragma once
// HDF5 output of a run, with an XDMF companion so ParaView opens the particle states.
//
// Layout (all SI units; read with h5py as f["frames/000003/position"][...]):
//   /                       attrs: format = "mfdem-state-1", time_step, note
//   /elements/radius        [elements]        m
//   /elements/body          [elements]        index of the owning body
//   /elements/material      [elements]        index into /materials names (attribute "names")
//   /elements/offset        [elements, 3]     from the body's centre, body frame, m
//   /bodies/mass            [bodies]          kg
//   /bodies/inertia         [bodies, 3]       principal moments, kg m^2
//   /walls                  attr "names"
//   /frames/NNNNNN          attrs: time (s), step
//       position, velocity, angular_velocity          [bodies, 3]
//       orientation                                    [bodies, 4]  (w, x, y, z)
//       unbalanced_force                               [bodies, 3]  net force before local
//                                                      damping, N (not in a "last good state")
//       element_position, element_velocity             [elements, 3] (for ParaView)
//       contact_body_a, contact_body_b                 [contacts]
//       contact_point, contact_force                   [contacts, 3] (force on body b, N)
//       wall_force                                     [walls, 3] force on each wall, N
//   /series/<name>          one value per frame: time, kinetic_energy, gravitational_energy,
//                           elastic_energy, dissipated_damping, dissipated_friction,
//                           dissipated_local, work_by_walls (J), and wall_force [frames, walls, 3]
// Every frame is flushed as it is written, so a run that stops keeps all earlier frames.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dem/simulation.hpp"

namespace mfdem::dem {

class StateFile {
 public:
  // Creates (truncates) `path` and `path` with extension .xdmf.
  StateFile(const std::filesystem::path& path, const Simulation& simulation, std::string note);
  ~StateFile();
  StateFile(const StateFile&) = delete;
  StateFile& operator=(const StateFile&) = delete;

  void write_frame(const Simulation& simulation);
  // Writes a saved snapshot (e.g. the last good state before a guard tripped) as a frame.
  void write_snapshot(const Simulation& simulation, const Simulation::Snapshot& snapshot,
                      const std::string& label);
  int frame_count() const { return frames_; }

 private:
  void append_series(const Simulation& simulation, double time);
  void append_xdmf_frame();

  std::filesystem::path path_;
  long long file_ = -1;
  int frames_ = 0;
  long long bodies_ = 0, elements_ = 0, walls_ = 0;
  std::vector<double> frame_times_;
  std::uint64_t xdmf_footer_at_ = 0;  // where the XDMF's footer starts
};

// What a frame holds, read back (for tests, restarts and post-processing).
struct StateFrame {
  double time = 0.0;
  long long step = 0;
  std::string label;  // e.g. "last good state" for the snapshot kept when a guard tripped
  std::vector<Vec3> position, velocity, angular_velocity;
  std::vector<Quat> orientation;
  std::vector<double> mass;             // kg
  std::vector<Vec3> inertia;            // principal, kg m^2
  std::vector<double> element_radius;
  std::vector<Index> element_body, element_material;
  std::vector<Vec3> element_offset;     // body frame, m
  std::vector<std::string> material_names;
  std::vector<Index> contact_body_a, contact_body_b;
  std::vector<Vec3> contact_force;
  std::vector<Vec3> wall_force;
};

int count_frames(const std::filesystem::path& path);
// (Re)writes `path` with extension .xdmf from the frames `path` holds: for a state file written
// under another name and renamed (the XDMF names its HDF5 file).
void write_xdmf_companion(const std::filesystem::path& path);
StateFrame read_frame(const std::filesystem::path& path, int frame);
// The bodies of a frame, ready for Simulation::add_clump (a sphere comes back as a one-pebble
// clump at its centre, which the solver treats exactly as a sphere). material_of maps the
// file's material indices to the new simulation's.
std::vector<ClumpSpec> bodies_of(const StateFrame& frame, const std::vector<int>& material_of);
// Every number of a frame that reaches the solver: throws std::invalid_argument naming the first
// body or element with a position, velocity or orientation that is not finite, or a mass,
// inertia or radius that is not positive and finite (a hand-edited or corrupted file). The
// caller adds the file's name.
void require_valid_frame(const StateFrame& frame);

}  // namespace mfdem::dem
