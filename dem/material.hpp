#pragma once
// Materials and per-pair contact parameters.
//
// Stiffness is mixed in series, as in PFC 4 and the reference paper:
//   kn = kn_a kn_b / (kn_a + kn_b),  ks likewise   [N/m]
// so two ballast stones with kn = 2e7 N/m each touch with a 1e7 N/m contact spring.
// (LAMMPS gran/hooke takes the contact value directly: a factor-2 trap when porting.)
// Friction, rolling friction and damping belong to the material pair: the pair value is the
// smaller of the two materials' values unless a pair override sets it.
#include <optional>
#include <string>
#include <vector>

namespace mfdem::dem {

struct Material {
  std::string name;
  double density = 2800.0;          // kg/m^3
  double normal_stiffness = 2e7;    // kn, N/m
  double shear_stiffness = 2e7;     // ks, N/m
  double friction = 0.5;            // Coulomb mu, -
  double rolling_friction = 0.0;    // mu_r, -  (|Mr| <= mu_r Rbar Fn)
  double damping_ratio = 0.0;       // beta_n, fraction of critical viscous normal damping
  double local_damping = 0.0;       // alpha, PFC-style non-viscous damping of the bodies made of it
};

// Contact parameters of one pair of materials, mixed once at set-up.
struct PairParameters {
  double normal_stiffness = 0.0;  // N/m
  double shear_stiffness = 0.0;   // N/m
  double friction = 0.0;
  double rolling_friction = 0.0;
  double damping_ratio = 0.0;
};

// Optional per-pair values that replace the mixed ones.
struct PairOverride {
  std::string material_a, material_b;
  std::optional<double> friction, rolling_friction, damping_ratio;
};

class MaterialTable {
 public:
  // Returns the index of the new material. Names must be unique.
  int add(const Material& material);
  void add_override(const PairOverride& override_values);
  int index_of(const std::string& name) const;  // -1 if unknown
  int size() const { return static_cast<int>(materials_.size()); }
  const Material& operator[](int i) const { return materials_[i]; }
  const std::vector<Material>& all() const { return materials_; }

  // Mixed parameters for the pair (a, b); symmetric.
  const PairParameters& pair(int a, int b) const { return pairs_[a * size() + b]; }

 private:
  void remix();
  std::vector<Material> materials_;
  std::vector<PairOverride> overrides_;
  std::vector<PairParameters> pairs_;
};

double series_stiffness(double ka, double kb);

}  // namespace mfdem::dem
