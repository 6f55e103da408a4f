#pragma once
// The lateral push test of a prepared bed (the definitions, also printed with every report):
// - the sleeper is driven along +x at `velocity` (reached after a linear speed-up over
//   ramp_distance, 0.1 mm by default), held along y, free vertically under its own weight (or,
//   as an option, held at its settled height, as a PFC wall sleeper), never rotating, until it has moved `distance` (u_end);
// - lateral force F(u) = minus the x component of the sum of the stones' contact forces on the
//   sleeper; each F(u) sample is the mean over the record interval ending at u (the per-step
//   force carries the rattle of single contacts);
// - peak lateral force = max F(u) over the samples, u in [0, u_end];
// - maximum particle contact force = max |f| over stone-stone contacts at u_end, with its
//   99.9 % quantile (nearest rank);
// - inertial number I = gamma_dot d / sqrt(p / rho): gamma_dot = velocity / sleeper height (the
//   passive wedge in front of the sleeper is about as deep as the sleeper), d the mean sieve
//   size, rho the stone density, p the mean stress of the stone contacts over the bed,
//   p = sum_c f_c . l_c / (3 V) (l_c the branch vector between the stones' centres, V the
//   bed's volume). I << 1e-3 is the quasi-static regime (GDR MiDi 2004).
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dem/simulation.hpp"
#include "studies/railway/model_bed.hpp"
#include "studies/railway/packing.hpp"

namespace mfdem::railway {

// Where the sleeper's lateral resistance comes from, as single-sleeper push tests split it
// (e.g. Le Pen & Powrie 2011, Proc. IMechE F 225:113-128): the parts of F(u) carried by its base
// (bottom face), its sides facing the cribs (the faces normal to the track), its ends facing the
// shoulders (normal to the push) and its top. Each contact counts to the face it leans on most
// (dem::box_face); the parts add up to F(u).
struct ResistanceParts {
  double base = 0.0, crib = 0.0, shoulder = 0.0, top = 0.0;  // N

  ResistanceParts& operator+=(const ResistanceParts& o) {
    base += o.base, crib += o.crib, shoulder += o.shoulder, top += o.top;
    return *this;
  }
  ResistanceParts operator/(double n) const { return {base / n, crib / n, shoulder / n, top / n}; }
};

struct ForceSample {
  double u = 0.0;       // sleeper displacement, m
  double force = 0.0;   // F(u), N
  double heave = 0.0;   // sleeper rise since the start, m
  double time = 0.0;    // s since the push began
  ResistanceParts parts;  // of F(u), mean over the same interval
  ResistanceParts support;  // of the upward force on the sleeper (its weight when at rest), same faces
  ResistanceParts pressing;  // the stones' normal force on each face group (compression), same faces
  std::int64_t contacts = 0;  // active element contacts (pairs and walls) at the sample's end: a step's cost
};

// The parts of F = -(force on the sleeper).x by face.
ResistanceParts resistance_parts(const std::array<dem::Vec3, dem::kBoxFaces>& faces);
// The parts of the upward force on the sleeper, (force on the sleeper).z, by face: how much of
// its weight the base carries and how much hangs on the cribs by side friction.
ResistanceParts support_parts(const std::array<dem::Vec3, dem::kBoxFaces>& faces);
// The normal force the stones press each face group with (N >= 0 on each face; a group's faces
// summed). Friction on the base and the crib sides gives at most mu times their pressing of F,
// up to the few edge contacts, which count to one face with their whole force; the ends give F by
// their normal force (shoulder part = leading end's minus trailing end's).
ResistanceParts pressing_parts(const std::array<dem::Vec3, dem::kBoxFaces>& faces);

struct NetworkSample {
  double u = 0.0;
  double mean_stress = 0.0;      // p, Pa
  double inertial_number = 0.0;
  double coordination = 0.0;     // stone-stone contacts per stone x 2
};

struct PushResult {
  std::string status = "finished";        // or "unstable": the results end at the last good state
  std::string message;
  double velocity = 0.0, distance = 0.0;  // m/s, m
  std::vector<ForceSample> curve;
  std::vector<NetworkSample> network;
  double peak_force = 0.0, u_at_peak = 0.0;
  // Mean F over the push: the work done on the bed / u_end. One slip event moves the peak of a
  // still-rising curve by several per cent; the mean much less (results/push_test, stop 23).
  double mean_force = 0.0;
  std::size_t peak_sample = 0;            // index of the peak in curve
  double max_contact_force = 0.0, contact_force_q999 = 0.0, mean_contact_force = 0.0;  // N
  double max_inertial_number = 0.0;
  double final_heave = 0.0;
  double sleeper_weight = 0.0;            // N, m g
  double sleeper_friction = 0.0;          // mu of the stone-sleeper contacts
  bool sleeper_held_vertically = false;   // true: held at its height, not free under its weight
  double time_step = 0.0, wall_seconds = 0.0;
  double time_step_limit = 0.0;           // s: the critical step the safety factor multiplies
  std::string time_step_reason;           // the contact type and bodies that set it
  std::int64_t steps = 0, stones = 0, elements = 0;
  std::vector<dem::ContactRecord> end_contacts;      // stone-stone, at u_end
  std::vector<dem::Vec3> start_position, end_position;  // stone centres
  std::vector<dem::Vec3> displacement;               // end - start (periodic images resolved)
  std::vector<std::int64_t> stone_id;
  // What the push ran on, so tables need not parse it from other files.
  ModelReport model;                  // the fidelity policy, mu_r, stones as clumps and balls
  std::uint64_t seed = 0;             // of the packing
  std::string config_hash;            // of the config text (config_hash())
  // The config whose materials, guards and push settings ran (name and file): the packing's own,
  // or another one given for a variant (`mfdem push --config`); the bed is always the packing's.
  std::string push_config;
  std::string revision;               // of the code (set by the caller that knows it)

  const ForceSample& at_peak() const { return curve[peak_sample]; }  // its parts, support, pressing
};

struct PushRun {
  double velocity = 0.0;   // m/s
  double distance = 0.0;   // m
  bool quiet = false;
  std::optional<std::filesystem::path> state_file;  // frames at the start, every mm, the end
};

// Pushes the sleeper of `packing`, with the materials, guards and push settings of `config`
// (the packing's own config, or another one for a variant). When a guard trips, the result
// holds everything up to that point, status "unstable" and the guard's message.
PushResult run_push(const Packing& packing, const PushStudyConfig& config, const PushRun& run);

// Work per unit displacement: sum of F_k (u_k - u_(k-1)) / u_last, each F_k the mean over its
// record interval (u before the first sample taken as 0). 0 for an empty curve or no displacement.
double mean_over_displacement(const std::vector<ForceSample>& curve);

// Mean F over consecutive windows of u, [0, w), [w, 2w), ... up to the last sample (a last,
// shorter window is kept when it spans at least 0.4 w): the work done in each window per unit
// displacement, each sample's F spread evenly over its record interval. Less noisy than the peak,
// and it shows where along the push two curves part (the rate check compares them per millimetre).
std::vector<double> window_mean_forces(const std::vector<ForceSample>& curve, double width);

// The x-z profile's area times the section length, minus the sleeper: V of the mean stress.
double bed_volume(const SectionGeometry& g);

// 64-bit FNV-1a of the text, as 16 hex digits: names a config's exact text in outputs.
std::string config_hash(const std::string& text);

// Nearest-rank quantile q in (0, 1] of the values (sorted in place).
double nearest_rank_quantile(std::vector<double>& values, double q);

}  // namespace mfdem::railway
