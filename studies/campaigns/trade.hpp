#pragma once
// `mfdem trade`: what the numerical knobs buy. Users buy speed with numerical settings as well as
// with fidelity (a larger time step, a faster push, more damping, softer stones); a trade study
// runs the model at each setting of each knob on the same seeds and measures its speedup and its
// error against a converged reference setting (every knob at its accurate end: the smallest step,
// the slowest push, no damping, full stiffness), paired by seed, with 95 % intervals; and it
// locates where each knob stops being safe: a setting the config refuses before it starts (a
// time step beyond the stability limit), or a run stopped by a guard (energy growth, an overlap
// beyond a fraction of a radius, a NaN), recorded with its message.
//
// A knob of the push alone (velocity, push damping) shares the seed's deposition and preparation
// with the reference; the others (time step, stiffness) prepare their own bed from the seed, so
// their difference includes the packing's response to the knob.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "studies/campaigns/compare.hpp"

namespace mfdem::campaigns {

struct KnobSpec {
  const char* name;     // on the command line
  const char* meaning;  // for tables and figures
  const char* unit;
  bool accurate_low;    // the accurate end is the smallest value (else the largest)
};
// time_step_safety (the fraction of the critical step), velocity (the push's, m/s), push_damping
// (local damping alpha of the stones while pushing), stiffness_scaling (the stones' kn and ks
// times this factor; 1 is Table 1), creep_ratio (the settling's creep criterion, [preparation];
// 0, off, is the accurate end).
const std::vector<KnobSpec>& trade_knobs();

struct KnobValues {
  const KnobSpec* spec = nullptr;
  std::vector<double> values;  // ascending, distinct
};
// "time_step_safety=0.2,0.4,0.6"; throws config::ConfigError naming `option` and the value for an
// unknown knob (naming the known ones), a value that is not a finite number, or a repeated value.
KnobValues parse_knob(const std::string& text, const std::string& option);

// The config with one knob set: its TOML text edited and parsed again, so that every check of a
// config applies (a value out of range throws config::ConfigError naming the key) and the run's key
// sees the change. The config's own value returns the config unchanged (its runs keep their keys).
railway::PushStudyConfig with_knob(const railway::PushStudyConfig& config, const KnobSpec& knob, double value);
// The knob's value in a config.
double knob_value(const railway::PushStudyConfig& config, const KnobSpec& knob);

struct TradeRequest {
  railway::PushStudyConfig config;
  Model model;
  std::vector<std::uint64_t> seeds;
  std::vector<KnobValues> knobs;
  double tolerance = 0.05;
};

// One setting: a knob at a value (the reference has no knob).
struct TradeSetting {
  std::optional<std::size_t> knob;  // index into request.knobs; none: the reference
  double value = 0.0;
  std::string label;                // "reference" or "velocity=0.05"
  std::string refused;              // the config's message when it refuses the setting before any run
};

struct TradePlan {
  railway::PushStudyConfig reference;    // every knob at its accurate end
  std::vector<TradeSetting> settings;    // the reference first, then each knob's other values
  CompareRequest compare;                // the settings that run, as models of a compare (the reference first)
  std::vector<std::size_t> compare_rows; // setting index of each compare model
};
// Throws config::ConfigError when the reference setting itself is refused.
TradePlan plan_trade(const TradeRequest& request);

struct TradeRow {
  TradeSetting setting;
  std::string status;  // "reference", "ran", "failed: MESSAGE" (a run stopped), "refused: MESSAGE"
  std::optional<ModelRow> measured;  // compare's row (speedups, paired differences) when it ran
};

struct KnobEdge {
  std::string knob;
  bool accurate_low = true;          // as the knob's KnobSpec
  double default_value = 0.0;        // the config's own value
  std::optional<double> last_safe;   // the farthest value from the accurate end that ran on every seed
  std::optional<double> first_unsafe;  // the nearest value beyond it that was refused or stopped
  std::string why;                   // the message of the first unsafe one
};

struct TradeTable {
  CompareTable compare;              // of the settings that ran
  std::vector<TradeRow> rows;        // in plan order
  std::vector<KnobEdge> edges;       // per knob
  std::vector<std::string> knob_names;  // of request.knobs, for TradeSetting::knob
};

TradeTable trade_table(const runs::RunStore& store, const TradeRequest& request, const TradePlan& plan);

void print_trade_table(std::ostream& out, const TradeTable& table);
void write_trade_markdown(std::ostream& out, const TradeTable& table);
// One row per setting: knob, value, status, speedups, the paired differences and their intervals.
void write_trade_csv(const std::filesystem::path& file, const TradeTable& table);

}  // namespace mfdem::campaigns
