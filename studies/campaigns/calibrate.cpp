#include "studies/campaigns/calibrate.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <sstream>

#include "fidelity/policy.hpp"
#include "studies/config/config_error.hpp"

namespace mfdem::campaigns {
namespace {

constexpr const char* kRolling = "mu_r";
constexpr const char* kBallFriction = "ball_mu";

bool is_material_parameter(const std::string& name) { return name == kRolling || name == kBallFriction; }

// The farthest a stone of the bed can lie from the sleeper's surface: below it to the floor, or
// beside it to the toe of the shoulder.
double farthest_from_sleeper(const railway::SectionGeometry& g) {
  return std::max(g.depth_under_sleeper, g.toe_half_width() - 0.5 * g.sleeper_length);
}

}  // namespace

RunOutputs mean_outputs(const std::vector<RunOutputs>& runs) {
  RunOutputs m;
  for (const auto& r : runs)
    m.peak_force += r.peak_force, m.contact_force += r.contact_force, m.push_wall += r.push_wall, m.wall += r.wall;
  const double n = double(runs.size());
  m.peak_force /= n, m.contact_force /= n, m.push_wall /= n, m.wall /= n;
  return m;
}

std::vector<CalibrationParameter> parse_calibration_parameters(const std::string& text, const std::string& policy,
                                                               const railway::PushStudyConfig& config,
                                                               const std::string& option,
                                                               const std::string& policy_option) {
  const auto refuse = [&](const std::string& why) {
    throw config::ConfigError(fmt::format("{} {}: {}", option, text, why));
  };
  fidelity::PolicySpec spec;
  try {
    spec = fidelity::parse_policy_spec(policy);
  } catch (const fidelity::PolicyError& e) {
    throw config::ConfigError(fmt::format("{} {}: {}", policy_option, policy, e.what()));
  }
  if (spec.name != "layer-by-height" && spec.name != "zone-by-distance")
    throw config::ConfigError(fmt::format("{} {}: expected layer-by-height or zone-by-distance (a policy with a "
                                          "ball layer whose extent can be calibrated)", policy_option, policy));
  std::vector<CalibrationParameter> out;
  std::stringstream entries(text);
  for (std::string entry; std::getline(entries, entry, ',');) {
    const auto equals = entry.find('='), colon = entry.find(':');
    if (equals == std::string::npos || colon == std::string::npos || colon < equals)
      refuse(fmt::format("'{}' is not NAME=LOWER:UPPER (e.g. mu_r=0:0.6)", entry));
    CalibrationParameter p{entry.substr(0, equals)};
    try {
      std::size_t used = 0;
      const std::string lo = entry.substr(equals + 1, colon - equals - 1), hi = entry.substr(colon + 1);
      p.lower = std::stod(lo, &used);
      if (used != lo.size()) throw std::invalid_argument(lo);
      p.upper = std::stod(hi, &used);
      if (used != hi.size()) throw std::invalid_argument(hi);
    } catch (const std::exception&) {
      refuse(fmt::format("'{}': the bounds must be numbers", entry));
    }
    if (!std::isfinite(p.lower) || !std::isfinite(p.upper) || !(p.upper > p.lower))
      refuse(fmt::format("'{}': an empty range (expected finite LOWER < UPPER)", entry));
    for (const auto& q : out)
      if (q.name == p.name) refuse(fmt::format("'{}' is given twice", p.name));
    if (is_material_parameter(p.name)) {
      if (p.lower < 0.0) refuse(fmt::format("'{}': {} must be >= 0", entry, p.name));
    } else {
      // A parameter of the policy: both ends must make a valid policy on this bed.
      const fidelity::BedScale scale{config.geometry.sleeper_base()};
      for (double v : {p.lower, p.upper}) {
        fidelity::PolicySpec at = spec;
        std::erase_if(at.parameters, [](const auto& q) { return q.name == "h" || q.name == "h_fraction" || q.name == "d"; });
        at.parameters.push_back({p.name, v});
        try {
          fidelity::PolicyRegistry::builtin().make(at, scale);
        } catch (const fidelity::PolicyError& e) {
          refuse(fmt::format("'{}': {} ({} lies outside the bed or the policy's parameters)", entry, e.what(), v));
        }
      }
      // The saving: every candidate must turn some stones into balls.
      if ((p.name == "h" || p.name == "h_fraction") && !(p.lower > 0.0))
        refuse(fmt::format("'{}': a layer height of {} leaves no ball (the all-clump model, which matches the "
                           "reference trivially); the lowest height is the smallest saving you accept", entry, p.lower));
      if (p.name == "d" && !(p.upper < farthest_from_sleeper(config.geometry)))
        refuse(fmt::format("'{}': a zone of {} m holds every stone of the bed (the farthest lies {:.3g} m from the "
                           "sleeper): no ball; the largest distance is the smallest saving you accept",
                           entry, p.upper, farthest_from_sleeper(config.geometry)));
    }
    out.push_back(p);
  }
  if (out.empty()) refuse("no parameter given");
  return out;
}

Model candidate_model(const std::string& policy, const std::vector<CalibrationParameter>& parameters,
                      const Eigen::VectorXd& values) {
  fidelity::PolicySpec spec = fidelity::parse_policy_spec(policy);
  Model m;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const std::string& name = parameters[k].name;
    const double v = values(static_cast<Eigen::Index>(k));
    if (name == kRolling) {
      m.rolling_friction = v;
    } else if (name == kBallFriction) {
      m.ball_friction = v;
    } else {
      // The calibrated extent replaces the policy's own (h and h_fraction name one height).
      std::erase_if(spec.parameters, [&](const auto& q) {
        return q.name == name || ((name == "h" || name == "h_fraction") && (q.name == "h" || q.name == "h_fraction"));
      });
      spec.parameters.push_back({name, v});
    }
  }
  m.policy = spec.text();
  return m;
}

PushRunner::PushRunner(runs::RunStore& store, railway::PushStudyConfig config,
                       std::optional<railway::PushStudyConfig> cheap, RunContext context, bool contact_quantile)
    : store_(store), config_(std::move(config)), cheap_(std::move(cheap)), context_(std::move(context)),
      contact_quantile_(contact_quantile) {}

RunOutputs PushRunner::run(const Model& model, std::uint64_t seed, calibration::Level level) {
  const railway::PushStudyConfig& config = level == calibration::Level::cheap && cheap_ ? *cheap_ : config_;
  ensure_push_run(store_, config, model, seed, context_);
  const std::string key = run_key(config, model, seed);
  const auto record = store_.find(key);
  if (!record) throw std::runtime_error(fmt::format("run {} is not in the store {} (computed elsewhere and not yet "
                                                    "published?)", key, store_.root().string()));
  if (!record->finished())
    throw std::runtime_error(fmt::format("run {} failed: {} (its record: {})", key, record->message,
                                         (store_.run_folder(key) / "run.toml").string()));
  RunOutputs out;
  out.peak_force = record->number(number::kPeakForce).value_or(NAN);
  out.contact_force = record->number(contact_quantile_ ? number::kContactForceQ999 : number::kMaxContactForce).value_or(NAN);
  out.push_wall = record->number(number::kPushWall).value_or(NAN);
  out.wall = out.push_wall + record->number(number::kPreparationWall).value_or(0.0);
  return out;
}

CalibrateResult run_calibration(CandidateRunner& runner, const CalibrateRequest& request) {
  if (request.seeds.empty()) throw std::invalid_argument("calibrate: at least one seed");
  CalibrateResult result;
  // The targets: the reference's means over the seeds (their standard error the targets' own
  // uncertainty in the posterior), or the numbers given.
  if (request.reference) {
    result.targets = *request.reference;
  } else {
    for (auto seed : request.seeds) result.reference_runs.push_back(runner.run(request.reference_model, seed, calibration::Level::expensive));
    const RunOutputs mean = mean_outputs(result.reference_runs);
    result.targets = {mean.peak_force, mean.contact_force};
    if (result.reference_runs.size() > 1) {
      std::vector<double> peaks, contacts;
      for (const auto& r : result.reference_runs) peaks.push_back(r.peak_force), contacts.push_back(r.contact_force);
      const double n = double(peaks.size());
      result.target_sd = {mean_interval(peaks).standard_deviation / std::sqrt(n),
                          mean_interval(contacts).standard_deviation / std::sqrt(n)};
    }
  }

  calibration::LoopOptions o;
  for (const auto& p : request.parameters) o.bounds.push_back({p.lower, p.upper});
  o.targets = {calibration::relative_target(result.targets[0]), calibration::relative_target(result.targets[1])};
  o.two_levels = request.two_levels;
  o.cheap_cost = request.cheap_cost;
  o.budget = request.budget;
  o.initial_expensive = request.initial_expensive;
  o.initial_cheap = request.initial_cheap;
  o.batch = request.batch;
  o.design_seed = request.design_seed;
  o.stop_improvement = request.stop_improvement;
  o.record = request.record;
  o.run_seeds = {0};  // unused: every candidate runs on all the request's seeds
  o.search.shortest_length = request.shortest_length;
  // A DEM run's identity: a run shared by both levels of the same config is one run.
  const auto run_id = [&](const Eigen::VectorXd& x, std::uint64_t seed, calibration::Level level) {
    std::string id = fmt::format("{} {}", level == calibration::Level::cheap && !request.cheap_on_same_config
                                              ? "cheap" : "expensive", seed);
    for (Eigen::Index k = 0; k < x.size(); ++k) id += fmt::format(" {:.17g}", x(k));
    return id;
  };
  std::map<std::string, double> wall_of;  // the runs made here, by identity
  const calibration::Evaluate evaluate = [&](const Eigen::VectorXd& x, std::uint64_t, calibration::Level level) {
    const Model model = candidate_model(request.policy, request.parameters, x);
    std::vector<RunOutputs> per_seed;
    for (auto seed : request.seeds_at(level)) {
      per_seed.push_back(runner.run(model, seed, level));
      wall_of[run_id(x, seed, level)] = per_seed.back().wall;
    }
    const RunOutputs mean = mean_outputs(per_seed);
    Eigen::VectorXd outputs(2);
    outputs << mean.peak_force, mean.contact_force;
    return outputs;
  };
  result.loop = calibration::run_calibration_loop(calibration::one_at_a_time(evaluate), o);
  // The cost of every distinct run: a restarted loop replays its record without running, so the
  // runs it replayed are looked up in the store.
  for (const auto& r : result.loop.runs)
    for (auto seed : request.seeds_at(r.level))
      if (const std::string id = run_id(r.parameters, seed, r.level); !wall_of.count(id))
        wall_of[id] = runner.run(candidate_model(request.policy, request.parameters, r.parameters), seed, r.level).wall;
  for (const auto& [id, wall] : wall_of) result.candidates_wall += wall;
  result.dem_runs = int(wall_of.size());

  result.surrogate.emplace(o.bounds, o.targets, o.kind, o.search);
  calibration::MisfitSurrogate& surrogate = *result.surrogate;
  surrogate.fit(result.loop.runs);
  result.calibrated = result.loop.history.back().returned;
  const auto predicted = surrogate.predict_outputs(result.calibrated);
  result.predicted = {predicted[0], predicted[1]};
  calibration::PosteriorOptions posterior;
  posterior.target_sd = {result.target_sd[0], result.target_sd[1]};
  posterior.seed = request.design_seed;
  result.posterior = calibration::calibration_posterior(surrogate, posterior);

  // Verified on fresh seeds against the reference on the same seeds.
  const Model calibrated = candidate_model(request.policy, request.parameters, result.calibrated);
  std::vector<double> peak, peak_reference, contact, contact_reference;
  for (auto seed : request.verify_seeds) {
    VerificationRow row{seed, runner.run(calibrated, seed, calibration::Level::expensive),
                        runner.run(request.reference_model, seed, calibration::Level::expensive)};
    peak.push_back(row.model.peak_force), peak_reference.push_back(row.reference.peak_force);
    contact.push_back(row.model.contact_force), contact_reference.push_back(row.reference.contact_force);
    result.verification.push_back(row);
  }
  std::vector<double> reference_walls;
  for (const auto& r : result.reference_runs) reference_walls.push_back(r.wall);
  for (const auto& row : result.verification) reference_walls.push_back(row.reference.wall);
  if (!reference_walls.empty()) result.reference_wall = mean_interval(reference_walls).mean;
  if (!result.verification.empty()) {
    result.peak_difference = mean_interval(relative_differences(peak, peak_reference));
    result.contact_difference = mean_interval(relative_differences(contact, contact_reference));
  }
  return result;
}

std::optional<Eigen::VectorXd> reference_parameters(const CalibrateRequest& request) {
  const Model& m = request.reference_model;
  const fidelity::PolicySpec spec = fidelity::parse_policy_spec(m.policy);
  if (spec.name != fidelity::parse_policy_spec(request.policy).name) return std::nullopt;
  Eigen::VectorXd values(static_cast<Eigen::Index>(request.parameters.size()));
  for (std::size_t k = 0; k < request.parameters.size(); ++k) {
    const std::string& name = request.parameters[k].name;
    double v = NAN;
    if (name == kRolling) v = m.rolling_friction.value_or(NAN);
    if (name == kBallFriction) v = m.ball_friction.value_or(NAN);
    for (const auto& q : spec.parameters)
      if (q.name == name) v = q.value;
    if (std::isnan(v)) return std::nullopt;
    values(static_cast<Eigen::Index>(k)) = v;
  }
  return values;
}

}  // namespace mfdem::campaigns
