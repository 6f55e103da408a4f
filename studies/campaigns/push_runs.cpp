#include "studies/campaigns/push_runs.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iostream>
#include <sstream>

#include "fidelity/policy.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/model_bed.hpp"
#include "studies/railway/preparation_checkpoint.hpp"
#include "studies/railway/push_study.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::campaigns {
namespace {

namespace fs = std::filesystem;

// Model keys beside the policy's own parameters in a --models entry.
constexpr const char* kRollingKey = "mu_r";
constexpr const char* kBallFrictionKey = "ball_mu";

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The deposited bed every model of `seed` starts from.
fs::path ensure_deposition(runs::RunStore& store, const railway::PushStudyConfig& config, std::uint64_t seed) {
  const std::string key = deposition_key(config, seed);
  return store.ensure_shared(key, [&](const fs::path& work) {
    railway::PushStudyConfig reference = with_model(config, Model{});
    reference.seed = seed;
    railway::PackRequest request;
    request.out = work;
    request.quiet = true;
    request.stop_after = "deposit";
    std::ostringstream ignored;
    const auto start = std::chrono::steady_clock::now();
    railway::pack_bed(reference, request, ignored);
    std::ofstream(work / "deposition.toml") << fmt::format("seed = {}\nwall_seconds = {:.6g}\n", seed,
                                                           seconds_since(start));
  });
}

double deposition_wall(const fs::path& folder) {
  return toml::parse_file((folder / "deposition.toml").string())["wall_seconds"].value_or(0.0);
}

}  // namespace

namespace {

// The config's TOML table without the top-level `keys`, serialised by toml++ (keys sorted,
// numbers in their shortest form): one written form of what the rest says.
std::string table_text_without(const railway::PushStudyConfig& config, std::initializer_list<const char*> keys) {
  toml::table table = toml::parse(config.text);
  for (const char* key : keys) table.erase(key);
  std::ostringstream text;
  text << table;
  return text.str();
}

// What determines a bed: the config without its name and [push] (settings of the push alone,
// which `mfdem trade` varies, share the seed's deposition and the model's prepared bed).
std::string bed_text(const railway::PushStudyConfig& config) { return table_text_without(config, {"name", "push"}); }

// A run's key from the text that stands for its config.
std::string run_key_of(const std::string& config_text, const railway::PushStudyConfig& config, const Model& model,
                       std::uint64_t seed) {
  const std::string what = model.text(config);
  const std::string hash =
      railway::config_hash(fmt::format("{}\n--model {}\n--seed {}\n", config_text, what, seed)).substr(0, 12);
  return runs::folder_name(fmt::format("s{}-{}-{}", seed, what, hash));
}

}  // namespace

std::string deposition_key(const railway::PushStudyConfig& config, std::uint64_t seed) {
  return fmt::format("deposit-{}-s{}", railway::config_hash(railway::deposition_text(config.text)), seed);
}

std::string prepared_bed_key(const railway::PushStudyConfig& config, const Model& model, std::uint64_t seed) {
  const std::string name = runs::folder_name(model.text(config));
  return fmt::format("bed-s{}-{}-{}", seed, name.substr(0, 60),
                     railway::config_hash(bed_text(config) + "\n" + model.text(config)).substr(0, 12));
}

std::string Model::text(const railway::PushStudyConfig& config) const {
  const std::string policy_text = fidelity::parse_policy_spec(policy).text();
  if (policy_text == railway::kReferencePolicy) return policy_text;
  const railway::PushStudyConfig c = with_model(config, *this);
  std::string out = fmt::format("{} mu_r={:g}", policy_text, c.fidelity.rolling_friction);
  if (c.fidelity.ball_friction) out += fmt::format(" ball_mu={:g}", *c.fidelity.ball_friction);
  return out;
}

std::vector<Model> parse_models(const std::string& list, const std::string& option) {
  const auto refuse = [&](const std::string& why) {
    throw config::ConfigError(fmt::format("{} {}: {}", option, list, why));
  };
  // Tokens split at ',' and ';'. After a ',' a token "key=value" without a ':' continues the
  // model before it (its parameters); any other token, and every token after a ';', starts one.
  std::vector<std::string> entries;
  std::string current;
  char separator = ';';
  const auto take = [&] {
    if (current.empty()) refuse("an empty entry (two separators in a row, or one at an end)");
    const bool continues = separator == ',' && !entries.empty() && current.find('=') != std::string::npos &&
                           current.find(':') == std::string::npos;
    if (continues) entries.back() += (entries.back().find(':') == std::string::npos ? ":" : ",") + current;
    else entries.push_back(current);
    current.clear();
  };
  for (char c : list) {
    if (c == ',' || c == ';') {
      take();
      separator = c;
    } else if (c != ' ') {
      current += c;
    }
  }
  take();
  std::vector<Model> models;
  for (const auto& entry : entries) {
    fidelity::PolicySpec spec;
    try {
      spec = fidelity::parse_policy_spec(entry);
    } catch (const fidelity::PolicyError& e) {
      refuse(fmt::format("'{}': {}", entry, e.what()));
    }
    Model m;
    std::vector<fidelity::PolicyParameter> own;
    for (const auto& p : spec.parameters) {
      if (p.name == kRollingKey) {
        if (p.value < 0.0) refuse(fmt::format("'{}': mu_r must be >= 0 (got {:g})", entry, p.value));
        m.rolling_friction = p.value;
      } else if (p.name == kBallFrictionKey) {
        if (p.value < 0.0) refuse(fmt::format("'{}': ball_mu must be >= 0 (got {:g})", entry, p.value));
        m.ball_friction = p.value;
      } else {
        own.push_back(p);
      }
    }
    spec.parameters = own;
    m.policy = spec.text();
    // Names and parameter names checked now (values against a bed later, per run).
    try {
      fidelity::PolicyRegistry::builtin().make(spec, fidelity::BedScale{1.0});
    } catch (const fidelity::PolicyError& e) {
      refuse(fmt::format("'{}': {} (known: {}; a model may add mu_r=, ball_mu=)", entry, e.what(),
                         fidelity::PolicyRegistry::builtin().listing()));
    }
    models.push_back(m);
  }
  if (models.empty()) refuse("no model given");
  return models;
}

Model parse_model(const std::string& text, const std::string& option) {
  const auto models = parse_models(text, option);
  if (models.size() != 1) throw config::ConfigError(fmt::format("{} {}: one model expected", option, text));
  return models.front();
}

railway::PushStudyConfig with_model(const railway::PushStudyConfig& config, const Model& model) {
  railway::PushStudyConfig c = config;
  c.fidelity.policy = model.policy;
  if (model.rolling_friction) c.fidelity.rolling_friction = *model.rolling_friction;
  if (model.ball_friction) c.fidelity.ball_friction = *model.ball_friction;
  return c;
}

std::string canonical_config_text(const railway::PushStudyConfig& config) {
  return table_text_without(config, {"name", "seed"});
}

std::string run_key(const railway::PushStudyConfig& config, const Model& model, std::uint64_t seed) {
  return run_key_of(canonical_config_text(config), config, model, seed);
}

runs::RunStore::Outcome ensure_push_run(runs::RunStore& store, const railway::PushStudyConfig& config,
                                        const Model& model, std::uint64_t seed, const RunContext& context) {
  railway::PushStudyConfig c = with_model(config, model);
  c.seed = seed;
  const std::string key = run_key(config, model, seed);
  // A store from before the keys' present form: the key hashed the config's text as written.
  store.adopt(run_key_of(config.text, config, model, seed), key);
  // Errors of the store itself (a full disk) stop the study; a run's own failure is recorded.
  const auto store_error = [](const std::exception& e) { return dynamic_cast<const fs::filesystem_error*>(&e); };
  return store.ensure(
      key, context.revision,
      [&](const fs::path& work) {
        const scene::ProgressMirror mirror(work / kRunProgressFile);  // for running_runs
        const fs::path deposition = ensure_deposition(store, config, seed);
        std::ostringstream ignored;
        std::ostream& out = context.quiet ? static_cast<std::ostream&>(ignored) : std::cout;
        runs::RunRecord record;
        record.labels = {{"model", model.text(config)}, {"config", config.name},
                         {"config_hash", railway::config_hash(config.text)}};
        record.numbers = {{number::kSeed, double(seed)}, {number::kDepositionWall, deposition_wall(deposition)}};

        // The model's prepared bed, shared by the runs that differ only in their push (trade's
        // velocity and push damping): made once, hard-linked into each run's folder.
        railway::PackRequest pack;
        pack.quiet = context.quiet;
        pack.deposit_from = deposition / "checkpoint.h5";
        pack.model_origin = "--models " + model.policy;
        const fs::path bed = store.ensure_shared(prepared_bed_key(config, model, seed), [&](const fs::path& bed_work) {
          pack.out = bed_work;
          const auto start = std::chrono::steady_clock::now();
          railway::pack_bed(c, pack, out);
          std::ofstream(bed_work / "preparation.toml") << fmt::format("seed = {}\nwall_seconds = {:.6g}\n", seed,
                                                                      seconds_since(start));
        });
        const double preparation_wall =
            toml::parse_file((bed / "preparation.toml").string())["wall_seconds"].value_or(0.0);
        const fs::path packing = work / "packing.h5";
        std::error_code linked;
        fs::create_hard_link(bed / "packing.h5", packing, linked);
        if (linked) fs::copy_file(bed / "packing.h5", packing);  // another file system: a copy

        railway::PushRequest push;
        push.out = work;
        push.quiet = context.quiet;
        push.convert = false;  // the model's own bed, made at the deposition
        push.revision = context.revision;
        push.model_origin = pack.model_origin;
        const railway::PushOutcome pushed =
            railway::push_bed(railway::load_packing(packing), packing, c, push, out);
        const railway::PushResult& r = pushed.result;
        record.labels.emplace_back("policy", r.model.policy);
        record.numbers.insert(record.numbers.end(),
                              {{number::kPeakForce, r.peak_force},
                               {"u_at_peak", r.u_at_peak},
                               {number::kMeanForce, r.mean_force},
                               {number::kMaxContactForce, r.max_contact_force},
                               {number::kContactForceQ999, r.contact_force_q999},
                               {"stones", double(r.stones)},
                               {number::kClumps, double(r.model.clumps)},
                               {number::kBalls, double(r.model.balls)},
                               {number::kElements, double(r.elements)},
                               {"elements_before", double(r.model.elements_before)},
                               {number::kContactsAtPeak, r.curve.empty() ? 0.0 : double(r.at_peak().contacts)},
                               {number::kPreparationWall, preparation_wall},
                               {number::kPushWall, r.wall_seconds},
                               {"time_step", r.time_step},
                               {"steps", double(r.steps)}});
        if (!pushed.finished()) {
          record.status = "failed";
          record.message = r.message.empty() ? "the push did not finish" : r.message;
        }
        return record;
      },
      store_error);
}

std::string running_runs(const runs::RunStore& store) {
  std::vector<std::string> parts;
  for (const auto& run : store.in_progress()) {
    const std::string line = scene::read_progress_mirror(run.work / kRunProgressFile);
    if (line.empty()) continue;  // a shared input, or a run that has not reported yet
    // The key without its hash: seed and model are what a reader wants.
    const auto dash = run.key.rfind('-');
    parts.push_back(fmt::format("{} {}", dash == std::string::npos ? run.key : run.key.substr(0, dash), line));
  }
  return fmt::format("{}", fmt::join(parts, ", "));
}

}  // namespace mfdem::campaigns
