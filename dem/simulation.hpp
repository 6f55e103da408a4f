#pragma once
// The DEM solver for spheres (and, through the body/element split, rigid clumps) and walls.
//
// One step is velocity Verlet (as LAMMPS fix nve/sphere):
//   1. half kick and drift of every body; element positions follow their body;
//   2. neighbour list rebuilt when an element has moved more than skin/2;
//   3. pair contacts evaluated in parallel, each writing only its own slot;
//   4. per body, in parallel: the body's contact forces summed in a fixed order, wall contacts,
//      gravity and local damping; second half kick.
// Every floating-point sum has an order that does not depend on the thread count, so 1 and 2
// threads give bitwise identical trajectories.
//
// The member functions are defined by stage: simulation.cpp (building and preparing the scene),
// simulation_step.cpp (step 1, the order of steps 1-4, stability checks), simulation_neighbors.cpp
// (step 2), simulation_pair_forces.cpp (step 3), simulation_gather.cpp (step 4) and
// simulation_diagnostics.cpp (energy, contacts, unbalanced force).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dem/bodies.hpp"
#include "dem/contact_batch.hpp"
#include "dem/contact_law.hpp"
#include "dem/domain.hpp"
#include "dem/material.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/stability.hpp"
#include "dem/time_step.hpp"
#include "dem/rigid_box.hpp"
#include "dem/wall.hpp"

namespace mfdem::dem {

// The automatic skin of the neighbour list: this fraction of the smallest element radius.
inline constexpr double kBaseSkinPerSmallestRadius = 0.2;

struct SimulationSettings {
  double time_step = 0.0;          // s; 0 selects the automatic step
  double time_step_safety = 0.2;   // automatic step = safety x critical step
  bool force_time_step = false;    // accept a given step above the critical one
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  // m/s^2
  double skin = 0.0;               // m; 0: automatic, kBaseSkinPerSmallestRadius x the smallest radius, more while bodies fly
  GuardSettings guards;
};

struct SphereSpec {
  Vec3 position = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  double radius = 0.01;
  int material = 0;
};

// A rigid clump: pebbles fixed in the body's principal frame. Mass properties come from the
// caller (fidelity::ClumpTemplate integrates them over the overlapping union).
struct Pebble {
  Vec3 offset = Vec3::Zero();  // from the centre of mass, principal frame, m
  double radius = 0.01;        // m
};

struct ClumpSpec {
  Vec3 position = Vec3::Zero();            // centre of mass, m
  Quat orientation = Quat::Identity();     // principal frame to world
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();    // world frame, rad/s
  double mass = 0.0;                       // kg
  Vec3 principal_inertia = Vec3::Zero();   // kg m^2
  std::vector<Pebble> pebbles;
  int material = 0;
};

// A sphere as a body: mass and inertia of a solid sphere of the given density (kg/m^3), one
// pebble at its centre (which the solver treats as a sphere, bitwise).
ClumpSpec sphere_body(const SphereSpec& sphere, double density);

// Energy account, J. With no damping, friction or work, `total()` is conserved.
struct EnergyReport {
  double kinetic_translational = 0.0;
  double kinetic_rotational = 0.0;
  double gravitational = 0.0;        // -sum m g.x (unwrapped positions)
  double elastic = 0.0;              // springs of all contacts
  double dissipated_damping = 0.0;   // viscous contact damping, cumulative
  double dissipated_friction = 0.0;  // sliding and rolling slip, cumulative
  double dissipated_local = 0.0;     // local (non-viscous) damping, cumulative
  double work_by_walls = 0.0;        // work done by moving walls and boxes and loads on boxes, cumulative

  double kinetic() const { return kinetic_translational + kinetic_rotational; }
  double dissipated() const { return dissipated_damping + dissipated_friction + dissipated_local; }
  // Conserved: mechanical energy plus everything dissipated minus the work put in.
  double total() const { return kinetic() + gravitational + elastic + dissipated() - work_by_walls; }
};

// One active contact, for output and metrics.
struct ContactRecord {
  Index body_a = -1, body_b = -1;  // body_b = -1 - wall index for a wall contact
  Vec3 point = Vec3::Zero();
  Vec3 force = Vec3::Zero();       // on b (on the wall for a wall contact)
  double overlap = 0.0;
};

// The spring state of one active contact, by index: a pair of elements (first < second), an
// element on a plane wall, or an element on a box. Saved with a settled bed, it lets a new
// simulation of the same bed resume with the friction forces that hold it up; without them a
// reloaded bed briefly carries no tangential force.
struct SpringState {
  enum class Kind : std::uint8_t { kPair = 0, kWall = 1, kBox = 2 };
  Kind kind = Kind::kPair;
  Index first = 0;   // element
  Index second = 0;  // element (pair), wall index or box index
  ContactHistory history;
};

class Simulation {
 public:
  Simulation(Domain domain, MaterialTable materials, SimulationSettings settings);

  Index add_sphere(const SphereSpec& sphere);
  Index add_clump(const ClumpSpec& clump);
  int add_wall(const PlaneWall& wall);
  int add_box(const RigidBox& box);

  // Springs to start from (contact_springs() of a simulation of the same elements, walls and
  // boxes, in the same order); applied by prepare() before the first force evaluation.
  void set_initial_springs(std::vector<SpringState> springs);
  // Fixes the time step (refusing one above the limit unless forced), builds the neighbour
  // list and evaluates the first forces. Call after adding bodies and walls. Throws
  // std::invalid_argument for a step above the limit and InitialOverlapError for bodies given
  // overlapping beyond guards.max_overlap_fraction.
  void prepare();
  // Changes the radius of element e from the next step on (after prepare()): a ball grown into
  // place. It takes effect after that step's drift, before its forces. Growth counts against
  // the neighbour list's skin as movement does, so no contact is missed; the elastic energy it
  // adds to the element's contacts counts as work put in (EnergyReport::work_by_walls); the time
  // step is not re-derived (give the step of the largest radii).
  void set_element_radius(Index e, double radius);
  // Advances one step; throws StabilityError when a guard trips (the last good state is kept,
  // see last_good_state()).
  void step();
  // The energy guard now (step() runs it every guards.check_interval steps): call it when a run
  // ends, so that a blow-up in its last steps is not reported finished. Throws StabilityError.
  void check_stability();

  double time() const { return time_; }
  std::int64_t step_count() const { return step_count_; }
  double time_step() const { return dt_; }
  const TimeStepLimit& time_step_limit() const { return limit_; }
  // The limit of the bodies and elements as added, without preparing (prepare() fixes it).
  TimeStepLimit stability_limit() const;

  const Bodies& bodies() const { return bodies_; }
  // For states (positions, velocities): masses are fixed after prepare() (each pair keeps its
  // dashpot from them).
  Bodies& mutable_bodies() { return bodies_; }
  const Elements& elements() const { return elements_; }
  const std::vector<PlaneWall>& walls() const { return walls_; }
  std::vector<PlaneWall>& mutable_walls() { return walls_; }
  const MaterialTable& materials() const { return materials_; }
  const Domain& domain() const { return domain_; }
  const SimulationSettings& settings() const { return settings_; }

  // Force the elements exert on wall w during the last step, N.
  const Vec3& wall_force(int w) const { return wall_force_[w]; }
  const std::vector<RigidBox>& boxes() const { return boxes_; }
  std::vector<RigidBox>& mutable_boxes() { return boxes_; }
  // Force the elements exert on box k during the last step, N.
  const Vec3& box_force(int k) const { return box_force_[k]; }
  // The same split by the face it acts on (box_face in rigid_box.hpp); box_force is their sum.
  const std::array<Vec3, kBoxFaces>& box_face_forces(int k) const { return box_face_force_[k]; }
  EnergyReport energy() const;
  std::vector<ContactRecord> contacts() const;
  std::vector<SpringState> contact_springs() const;  // every active contact, pairs first
  Index active_contact_count() const;
  // Mean unbalanced force ratio (PFC's equilibrium measure): the mean over bodies of the
  // magnitude of the net force (contacts and gravity, before local damping) over the mean
  // magnitude of the body-body contact forces. Infinite while no two bodies touch.
  double unbalanced_force_ratio() const;
  std::int64_t neighbour_rebuilds() const { return rebuilds_; }

  // State at the last passed stability check (positions, velocities), kept for output when a
  // guard trips.
  struct Snapshot {
    double time = 0.0;
    std::int64_t step = 0;
    std::vector<Vec3> position, velocity, angular_velocity;
    std::vector<Quat> orientation;
  };
  const std::optional<Snapshot>& last_good_state() const { return last_good_; }

 private:
  void drift_and_kick();
  double drift_clump_batch(Index k, double half);
  void maybe_rebuild();
  void rebuild();
  void release_opened_contacts();
  double release_pair(Index p, const Vec3& separation);
  void evaluate_forces();  // pairs, walls, boxes, gravity; the second half kick
  template <bool kPointBodies>
  void evaluate_forces_of();
  void prepare_gather();
  template <bool kPointBodies>
  void gather_chunk(Index chunk);
  void finish_gather();
  void check_boxes_clear_periodic_faces() const;
  void apply_initial_springs();
  std::vector<SpringState> initial_springs_;
  void update_element_positions(Index b);
  void place_elements(Index b, const Mat3& rotation);  // elements of body b, orientation given
  Index add_body(const ClumpSpec& body);
  [[gnu::always_inline]] inline void kick(Index b, const Vec3& force, const Vec3& torque, double h);
  Snapshot snapshot() const;
  // Calls f(p) for every pair p of the neighbour list that element e belongs to.
  template <class F>
  void for_each_pair_of(Index e, F&& f) const {
    for (Index p = pairs_.row_start[e]; p < pairs_.row_start[e + 1]; ++p) f(p);
    for (Index k = pairs_.as_second_start[e]; k < pairs_.as_second_start[e + 1]; ++k) f(pairs_.as_second_pair[k]);
  }
  // (r_i + r_j)^2 of pair p at the present radii: what overlapping() tests against.
  double reach2_of(Index p) const {
    const double reach = elements_.radius[pairs_.first[p]] + elements_.radius[pairs_.second[p]];
    return reach * reach;
  }
  // Elastic energy of one active contact (energy()), and of all contacts of element e.
  double pair_elastic_energy(Index p) const;
  double wall_elastic_energy(Index e, std::size_t w) const;
  double box_elastic_energy(Index e, std::size_t k) const;
  double element_elastic_energy(Index e) const;
  // Throws StabilityError naming the step being taken, or the one just completed.
  void fail(const std::string& what, Index body, bool step_completed = false) const;

  Domain domain_;
  MaterialTable materials_;
  SimulationSettings settings_;
  Bodies bodies_;
  Elements elements_;
  std::vector<PlaneWall> walls_;
  std::vector<std::uint8_t> point_body_;  // one element at the centre: rotation needs no frame
  std::vector<Index> clump_bodies_;       // the bodies that are not point bodies, in order
  static constexpr int kRotationBatch = 4;  // clumps rotated side by side (free_rotations)
  static constexpr double kMaxSkinFactor = 5.0;  // the automatic skin's largest multiple of its base (adaptive_skin)
  std::vector<Vec3> wrap_total_;   // sum of periodic wrap shifts per body (for energy)

  PairList pairs_;
  // A pair's springs (ContactHistory) in two arrays: the tangential spring and the dashpot's
  // last force, which every contact reads and writes each step, packed in 32 bytes; and the
  // rolling spring apart, so that a run without rolling resistance never loads it.
  struct alignas(32) PairSpring {
    Vec3 shear_force = Vec3::Zero();
    double damping_force = 0.0;
  };
  std::vector<PairSpring> pair_spring_;
  std::vector<Vec3> pair_rolling_;
  ContactHistory pair_history(Index p) const;
  void set_pair_history(Index p, const ContactHistory& h);
  // Pairs that cross two threads' blocks are stored before they are summed.
  std::vector<Vec3> pair_force_;         // on second (stored pairs only; contact_force for any)
  std::vector<Vec3> pair_torque_first_;  // about the first element's centre
  std::vector<Vec3> pair_torque_second_;
  std::vector<std::uint8_t> pair_active_;
  std::vector<double> pair_dashpot_;     // cn of each pair, N s/m (set by rebuild)
  std::vector<double> pair_reach2_;      // (ri + rj)^2 of each pair, m^2 (set by rebuild)
  std::vector<Vec3> element_force_, element_torque_;  // pair contacts summed per element
  std::vector<double> pair_damping_, pair_friction_;  // energy of stored pairs this step, J
  std::vector<double> row_damping_, row_friction_;    // energy of each element's row, J
  bool all_point_bodies_ = false;                      // spheres only: no body indirection
  bool any_rolling_ = false;                           // some material pair has mu_r > 0
  int one_material_ = -1;                              // the material of every element, or -1
  // The lanes every pair of this run shares (zero levers of spheres, one material's
  // parameters, zero rolling springs), set once so that load_lane can skip them.
  template <bool kPointBodies>
  void prefill_batch(ContactBatch& batch) const;
  // Pair p, which touches (|d|^2 = d2 < reach^2), into lane `lane` of the batch, and its
  // updated springs back from it (dem/contact_batch.hpp).
  template <bool kPointBodies>
  [[gnu::always_inline]] inline void load_lane(ContactBatch& batch, int lane, Index p, const Vec3& d, double d2) const;
  [[gnu::always_inline]] inline void store_springs(const ContactBatch& batch, int lane, Index p);
  // The bodies split among the threads of the step's loops (drift, pairs, gather), planned at
  // the first loop after each build or rebalance. Where the blocks end never changes a result.
  struct alignas(64) BusyTime {  // one cache line per thread
    double seconds = 0.0;
  };
  struct PairBlocks {
    int threads = 0;                 // 0: not planned for the current list
    std::vector<double> share;       // block t starts at share[t] of the neighbour list
    std::vector<Index> body_start;   // block t: bodies [body_start[t], body_start[t + 1])
    std::vector<Index> crossing;     // pairs whose second element lies in a later block
    std::vector<Index> taken_start;  // block t takes taken[taken_start[t] .. taken_start[t + 1])
    std::vector<Index> taken;        // crossing pairs by the second element (in block order), then pair
    std::vector<BusyTime> busy;      // per thread: pair-loop time since the last balance
  };
  PairBlocks pair_blocks_;
  static constexpr int kBalanceInterval = 100;  // steps between balance_blocks
  Index pair_block_start(int t) const;
  void plan_pair_blocks(int threads);
  void balance_blocks();
  int team_size() const;  // threads of the step's parallel regions
  // Called by each thread of a team: the plan for this team, its bodies, its chunks of bodies.
  const PairBlocks& team_plan();
  std::pair<Index, Index> thread_bodies();
  std::pair<Index, Index> thread_chunks();
  Vec3 contact_force(Index p, const Vec3& d) const;  // of an active pair at separation d, on its second element
  // Vector from pair p's first element to its second (periodic image included).
  [[gnu::always_inline]] inline Vec3 separation(Index p, const Vec3& length) const {
    const Vec3& xi = elements_.position[pairs_.first[p]];
    const Vec3& xj = elements_.position[pairs_.second[p]];
    // Without periodic axes every image is zero: skip the int-to-double conversions.
    return any_periodic_ ? Vec3(xj + image_shift(pairs_.image[p], length) - xi) : Vec3(xj - xi);
  }
  // Pair p's elements overlap at squared separation d2 (the one test of touching, so that the
  // pair loop's filter, its batch loading and the release of opened contacts agree to the bit).
  [[gnu::always_inline]] inline bool overlapping(Index p, double d2) const {
    return !(d2 >= pair_reach2_[p]);  // a NaN is not "apart": the finiteness guards name its body
  }
  bool any_periodic_ = false;
  // x moved to its periodic image nearest the box centre, so that a box sees the elements across
  // a periodic face; x itself, to the bit, when no image is nearer. It runs for every element and
  // box at every step: a comparison per periodic axis, the division only past half a length.
  [[gnu::always_inline]] inline Vec3 box_image(const Vec3& x, const RigidBox& box) const {
    if (!any_periodic_) return x;
    Vec3 image = x;
    for (int a = 0; a < 3; ++a) {
      if (!domain_.periodic[a]) continue;
      const double d = x[a] - box.centre[a], length = domain_.max[a] - domain_.min[a];
      if (std::abs(d) > 0.5 * length) image[a] -= length * std::round(d / length);
    }
    return image;
  }
  std::vector<std::vector<Index>> pair_work_;  // per thread: the pairs phase B visits
  std::vector<ContactHistory> wall_history_;  // [element * walls + wall]
  std::vector<std::uint8_t> wall_active_;     // [element * walls + wall]
  void scan_walls();
  std::vector<std::uint8_t> near_wall_;       // per element: may touch a plane wall (scan_walls)
  std::vector<Vec3> wall_scan_point_, wall_scan_normal_;  // the walls at the last scan
  bool scan_walls_ = true;
  std::vector<Vec3> build_position_;          // element positions at the last build
  double skin_ = 0.0;       // of the current list
  double base_skin_ = 0.0;  // given, or 0.2 x the smallest radius
  double largest_radius_ = 0.0;  // of any element, m (set by prepare)
  double adaptive_skin() const;

  std::vector<RigidBox> boxes_;
  std::vector<ContactHistory> box_history_;   // [element * boxes + box]
  std::vector<std::uint8_t> box_active_;
  std::vector<Vec3> box_force_;
  std::vector<std::array<Vec3, kBoxFaces>> box_face_force_;        // box_force_ split by face
  std::vector<std::array<Vec3, kBoxFaces>> chunk_box_face_force_;  // [chunk * boxes + box]
  void kick_boxes(double h);
  std::vector<Vec3> wall_force_;
  std::vector<Vec3> chunk_wall_force_;  // [chunk * walls + wall]
  struct ChunkEnergy {
    double damping = 0.0, friction = 0.0, local = 0.0, wall_work = 0.0;
    Index bad_body = -1;
    Index bad_pair = -1;
  };
  std::vector<ChunkEnergy> pair_chunk_energy_, body_chunk_energy_;
  double max_move2_ = 0.0;
  double radius_growth_ = 0.0;         // largest growth of an element's radius since the last build, m
  std::vector<double> build_radius_;   // element radii at the last build
  std::vector<std::pair<Index, double>> pending_radius_;  // set_element_radius, for the next step
  void apply_pending_radii();
  bool gather_and_kick_ = true;  // false only for the first force evaluation

  double dt_ = 0.0;
  TimeStepLimit limit_;
  double time_ = 0.0;
  std::int64_t step_count_ = 0;
  std::int64_t rebuilds_ = 0;
  bool prepared_ = false;

  double dissipated_damping_ = 0.0, dissipated_friction_ = 0.0, dissipated_local_ = 0.0;
  double work_by_walls_ = 0.0;
  double energy_reference_ = 0.0;
  double energy_scale_ = 0.0;
  std::optional<Snapshot> last_good_;
};

// Half kick: v += h F/m; the angular momentum takes h T. A point body (sphere) has an isotropic
// inertia, so w += h T/I directly; a clump goes through its body-frame angular momentum.
inline void Simulation::kick(Index b, const Vec3& force, const Vec3& torque, double h) {
  bodies_.velocity[b] += (h / bodies_.mass[b]) * force;
  if (point_body_[b]) {
    bodies_.angular_velocity[b] += h * torque.cwiseQuotient(bodies_.inertia[b]);
    return;
  }
  // l_body += h R^T T, so w = R (l_body / I) gains R ((h R^T T) / I): no round trip of w
  // through the body frame, and one rotation matrix instead of three quaternion rotations.
  const Mat3 r = bodies_.orientation[b].toRotationMatrix();
  bodies_.angular_velocity[b] += r * (h * (r.transpose() * torque)).cwiseQuotient(bodies_.inertia[b]);
}

}  // namespace mfdem::dem
