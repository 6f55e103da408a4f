#pragma once
// Fidelity policies: which stones of a bed stay rigid multi-sphere clumps and which become single
// balls (the multi-layer model of Jia, Markine & Guo 2023: clumps where stones touch the sleeper,
// balls with rolling resistance below). A policy sees a stone only as plain numbers of its
// geometry relative to the bed and the sleeper (StoneGeometry), so it can be tested without a
// simulation and a new one is a predicate registered under a name.
//
// Built in (PolicyRegistry::builtin(); written NAME or NAME:key=value,key=value):
//   all-clump                 every stone a clump: the reference model
//   all-ball                  every stone a ball
//   layer-by-height:h=H       stones whose centre of mass lies below H (m above the floor) become
//                             balls: the paper's model. Or h_fraction=F: H = F x the depth from
//                             the floor to the sleeper base. H in metres is primary; both are
//                             kept and printed. 0 <= H <= the sleeper base.
//   zone-by-distance:d=D      stones whose nearest pebble surface lies within D (m) of the
//                             sleeper's surface stay clumps, the others become balls: the
//                             paper's proposed refinement. D >= 0.
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace mfdem::fidelity {

// The one type for the choice of fidelity of a stone.
enum class Representation { clump, ball };
// "clump" or "ball" (a config's choice, already checked) as the type.
Representation representation_named(std::string_view name);

// What a policy sees of one stone.
struct StoneGeometry {
  double height = 0.0;       // centre of mass above the floor, m
  double sleeper_gap = 0.0;  // nearest pebble surface to the sleeper's surface, m (0: touching)
};

// The bed a policy's parameters are checked and scaled against.
struct BedScale {
  double sleeper_base = 0.0;  // height of the sleeper's base above the floor, m
};

using StonePredicate = std::function<Representation(const StoneGeometry&)>;

struct PolicyParameter {
  std::string name;
  double value = 0.0;
};

struct Policy {
  std::string name;
  std::vector<PolicyParameter> parameters;  // as resolved (layer-by-height: h and h_fraction)
  StonePredicate choose;

  // "layer-by-height:h=0.15,h_fraction=0.5": the name and every resolved parameter.
  std::string describe() const;
  double parameter(std::string_view name) const;  // throws std::out_of_range if absent
};

// A policy as written: a name and the parameters given.
struct PolicySpec {
  std::string name;
  std::vector<PolicyParameter> parameters;
  std::string text() const;  // back to NAME[:key=value,...]
};

// A bad policy: the message names the parameter ("" for the name), the value and what was
// expected; callers prefix the file and key or the command-line option.
struct PolicyError : std::invalid_argument {
  PolicyError(std::string parameter, const std::string& message)
      : std::invalid_argument(message), parameter(std::move(parameter)) {}
  std::string parameter;
};

// Parses NAME or NAME:key=value[,key=value...]; values must be finite numbers.
PolicySpec parse_policy_spec(std::string_view text);

// How a named policy is made from its parameters and the bed: checks them (throwing
// PolicyError) and returns the policy.
using PolicyMaker = std::function<Policy(const PolicySpec&, const BedScale&)>;

struct PolicyKind {
  std::string name;
  std::string summary;                  // one line, for help texts and errors
  std::vector<std::string> parameters;  // the names it accepts
  PolicyMaker make;
};

class PolicyRegistry {
 public:
  // The registry with the built-in policies; a C++ user adds to it.
  static PolicyRegistry& builtin();
  // Throws std::invalid_argument when the name is taken.
  void add(PolicyKind kind);
  // A predicate on a stone with no parameters, registered under `name`.
  void add(const std::string& name, const std::string& summary, StonePredicate choose);
  // Throws PolicyError for an unknown name or parameter, a missing or bad value.
  Policy make(const PolicySpec& spec, const BedScale& scale) const;
  Policy make(std::string_view text, const BedScale& scale) const { return make(parse_policy_spec(text), scale); }
  // "all-clump, all-ball, layer-by-height (h or h_fraction), zone-by-distance (d)".
  std::string listing() const;

 private:
  std::vector<PolicyKind> kinds_;
};

}  // namespace mfdem::fidelity
