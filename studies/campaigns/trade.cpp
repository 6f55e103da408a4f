#include "studies/campaigns/trade.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "studies/config/config_error.hpp"
#include "studies/railway/push_study.hpp"

namespace mfdem::campaigns {
namespace {

namespace fs = std::filesystem;

const KnobSpec* find_knob(const std::string& name) {
  for (const auto& k : trade_knobs())
    if (name == k.name) return &k;
  return nullptr;
}

double accurate_end(const KnobValues& k) { return k.spec->accurate_low ? k.values.front() : k.values.back(); }

// A knob's values from its accurate end outwards.
std::vector<double> outward_values(const KnobValues& k) {
  std::vector<double> v = k.values;
  if (!k.spec->accurate_low) std::reverse(v.begin(), v.end());
  return v;
}

toml::table& subtable(toml::table& t, const char* name) {
  if (!t.contains(name) || !t[name].is_table()) t.insert_or_assign(name, toml::table{});
  return *t[name].as_table();
}

// Applies every knob: `varied` at `value`, the others at their accurate ends.
railway::PushStudyConfig setting_config(const TradeRequest& r, std::optional<std::size_t> varied, double value) {
  railway::PushStudyConfig c = r.config;
  for (std::size_t k = 0; k < r.knobs.size(); ++k)
    c = with_knob(c, *r.knobs[k].spec, varied && *varied == k ? value : accurate_end(r.knobs[k]));
  return c;
}

std::string value_text(double v) { return fmt::format("{:g}", v); }

std::string verdict_words(const ModelRow& r) {
  if (r.peak_verdict == Verdict::within && r.contact_verdict == Verdict::within) return "within";
  if (r.peak_verdict == Verdict::outside || r.contact_verdict == Verdict::outside) return "outside";
  return "undecided";
}

// A row's cells after its label: push and total speedup, the three differences, the status.
std::array<std::string, 6> row_cells(const TradeRow& r, double tolerance) {
  if (!r.measured) return {"-", "-", "-", "-", "-", r.status};
  const ModelRow& m = *r.measured;
  const bool reference = !r.setting.knob;
  return {speedup_text(m.push_speedup),
          speedup_text(m.total_speedup),
          reference ? "0" : percent_interval(m.peak_force.difference),
          reference ? "0" : percent_interval(m.max_contact_force.difference),
          reference ? "0" : percent_interval(m.curve_difference),
          reference || r.status != "ran" ? r.status : fmt::format("ran, {} {:.0f} %", verdict_words(m), 100.0 * tolerance)};
}

std::string edge_line(const KnobEdge& e) {
  std::string line = fmt::format("{}: ", e.knob);
  if (!e.first_unsafe) {
    line += e.last_safe ? fmt::format("every value ran, up to {}; the edge lies beyond the values tried",
                                      value_text(*e.last_safe))
                        : "no value ran";
  } else {
    line += e.last_safe ? fmt::format("safe at {}, unsafe at {} ({})", value_text(*e.last_safe),
                                      value_text(*e.first_unsafe), e.why)
                        : fmt::format("unsafe already at {} ({})", value_text(*e.first_unsafe), e.why);
  }
  if (e.last_safe && e.default_value > 0.0 && *e.last_safe > 0.0) {
    const double margin = e.accurate_low ? *e.last_safe / e.default_value : e.default_value / *e.last_safe;
    line += fmt::format("; the config's {} keeps a margin of at least {:.2f}x to the last safe value",
                        value_text(e.default_value), margin);
  }
  return line;
}

// The edges, one line each after `bullet`.
void print_edges(std::ostream& out, const TradeTable& t, const char* bullet) {
  for (const auto& e : t.edges) fmt::print(out, "{}{}\n", bullet, edge_line(e));
}

}  // namespace

const std::vector<KnobSpec>& trade_knobs() {
  static const std::vector<KnobSpec> knobs = {
      {"time_step_safety", "fraction of the critical time step", "", true},
      {"velocity", "push velocity", "m/s", true},
      {"push_damping", "local damping of the stones while pushing", "", true},
      {"stiffness_scaling", "factor on the stones' normal and shear stiffness", "", false},
      {"creep_ratio", "creep of the stones that ends a settling (0: the force ratio alone)", "", true}};
  return knobs;
}

KnobValues parse_knob(const std::string& text, const std::string& option) {
  const auto refuse = [&](const std::string& why) {
    std::string names;
    for (const auto& k : trade_knobs()) names += (names.empty() ? "" : ", ") + std::string(k.name);
    throw config::ConfigError(fmt::format("{} {}: {} (expected NAME=V1,V2,... with NAME one of {})", option, text, why, names));
  };
  const auto equals = text.find('=');
  if (equals == std::string::npos) refuse("no '='");
  KnobValues k;
  k.spec = find_knob(text.substr(0, equals));
  if (k.spec == nullptr) refuse(fmt::format("unknown knob '{}'", text.substr(0, equals)));
  std::stringstream in(text.substr(equals + 1));
  for (std::string v; std::getline(in, v, ',');) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(v, &used);
    } catch (const std::exception&) {
      refuse(fmt::format("'{}' is not a number", v));
    }
    if (used != v.size() || !std::isfinite(x)) refuse(fmt::format("'{}' is not a finite number", v));
    k.values.push_back(x);
  }
  if (k.values.empty()) refuse("no value");
  std::sort(k.values.begin(), k.values.end());
  if (std::adjacent_find(k.values.begin(), k.values.end()) != k.values.end()) refuse("a value is given twice");
  return k;
}

railway::PushStudyConfig with_knob(const railway::PushStudyConfig& config, const KnobSpec& knob, double value) {
  // The config's own value: the config as it is, so that its runs (a compare study's reference in
  // the same store) keep their keys and are found.
  if (knob_value(config, knob) == value) return config;
  toml::table t = toml::parse(config.text);
  const std::string name = knob.name;
  if (name == "time_step_safety") t.insert_or_assign("time_step_safety", value);
  else if (name == "velocity") subtable(t, "push").insert_or_assign("velocity", value);
  else if (name == "push_damping") subtable(t, "push").insert_or_assign("local_damping", value);
  else if (name == "creep_ratio") subtable(t, "preparation").insert_or_assign("creep_ratio", value);
  else if (name == "stiffness_scaling") {
    // The stones' material written out whole (a [materials.ballast] table needs every key).
    const dem::Material& m = config.ballast;
    toml::table ballast{{"density", m.density},
                        {"normal_stiffness", m.normal_stiffness * value},
                        {"shear_stiffness", m.shear_stiffness * value},
                        {"friction", m.friction},
                        {"rolling_friction", m.rolling_friction},
                        {"damping_ratio", m.damping_ratio},
                        {"local_damping", m.local_damping}};
    subtable(t, "materials").insert_or_assign("ballast", ballast);
  } else {
    throw std::logic_error("with_knob: unknown knob " + name);
  }
  std::ostringstream text;
  text << t << '\n';
  return railway::parse_push_config(text.str(), config.source);
}

double knob_value(const railway::PushStudyConfig& config, const KnobSpec& knob) {
  const std::string name = knob.name;
  if (name == "time_step_safety") return config.time_step_safety;
  if (name == "velocity") return config.push.velocity;
  if (name == "push_damping") return config.push.local_damping;
  if (name == "creep_ratio") return config.preparation.creep_ratio;
  return 1.0;  // stiffness_scaling: relative to the config's own stones
}

TradePlan plan_trade(const TradeRequest& r) {
  TradePlan plan;
  std::string reference_label = "reference:";
  for (const auto& k : r.knobs) reference_label += fmt::format(" {}={}", k.spec->name, value_text(accurate_end(k)));
  try {
    plan.reference = setting_config(r, std::nullopt, 0.0);
  } catch (const config::ConfigError& e) {
    throw config::ConfigError(fmt::format("--knob: the reference setting ({}) is refused: {}", reference_label, e.what()));
  }
  plan.settings.push_back({std::nullopt, 0.0, reference_label, ""});
  plan.compare.config = plan.reference;
  plan.compare.seeds = r.seeds;
  plan.compare.tolerance = r.tolerance;
  plan.compare.reference = 0;
  const auto add_run = [&](const railway::PushStudyConfig& c, const std::string& label) {
    plan.compare_rows.push_back(plan.settings.size() - 1);
    plan.compare.models.push_back(r.model);
    plan.compare.model_configs.push_back(c);
    plan.compare.model_labels.push_back(label);
  };
  add_run(plan.reference, reference_label);
  for (std::size_t k = 0; k < r.knobs.size(); ++k) {
    for (double v : outward_values(r.knobs[k])) {
      if (v == accurate_end(r.knobs[k])) continue;
      TradeSetting s{k, v, fmt::format("{}={}", r.knobs[k].spec->name, value_text(v)), ""};
      std::optional<railway::PushStudyConfig> c;
      try {
        c = setting_config(r, k, v);
        // The push's own limits, checked here rather than after the setting's preparation.
        railway::check_push_motion(c->push.velocity, c->push.distance, c->push.record_interval, "[push]");
      } catch (const config::ConfigError& e) {
        // The message names a line of the edited text, not of the user's file: name the knob instead.
        std::string why = e.what();
        for (std::size_t colon = why.find(':'); colon != std::string::npos; colon = why.find(':', colon + 1)) {
          std::size_t end = colon + 1;  // "FILE:LINE: " ends where the digits after a colon meet ": "
          while (end < why.size() && std::isdigit(static_cast<unsigned char>(why[end]))) ++end;
          if (end > colon + 1 && why.compare(end, 2, ": ") == 0) {
            why = why.substr(end + 2);
            break;
          }
        }
        s.refused = fmt::format("--knob {}: {}", s.label, why);
        c.reset();
      }
      plan.settings.push_back(s);
      if (c) add_run(*c, s.label);
    }
  }
  return plan;
}

TradeTable trade_table(const runs::RunStore& store, const TradeRequest& request, const TradePlan& plan) {
  TradeTable t;
  t.compare = compare_table(store, plan.compare);
  t.compare.config = request.config.name;
  for (std::size_t s = 0; s < plan.settings.size(); ++s) {
    TradeRow row;
    row.setting = plan.settings[s];
    const auto at = std::find(plan.compare_rows.begin(), plan.compare_rows.end(), s);
    if (!row.setting.refused.empty()) {
      row.status = "refused: " + row.setting.refused;
    } else if (at != plan.compare_rows.end()) {
      const ModelRow& m = t.compare.rows[static_cast<std::size_t>(at - plan.compare_rows.begin())];
      row.measured = m;
      if (!m.failures.empty()) row.status = "failed: " + m.failures.front();
      else if (m.seeds < request.seeds.size()) row.status = fmt::format("incomplete: {} of {} seeds", m.seeds, request.seeds.size());
      else row.status = s == 0 ? "reference" : "ran";
    }
    t.rows.push_back(row);
  }
  for (std::size_t k = 0; k < request.knobs.size(); ++k) {
    const KnobValues& knob = request.knobs[k];
    t.knob_names.emplace_back(knob.spec->name);
    KnobEdge e;
    e.knob = knob.spec->name;
    e.accurate_low = knob.spec->accurate_low;
    e.default_value = knob_value(request.config, *knob.spec);
    for (double v : outward_values(knob)) {
      const TradeRow* row = nullptr;
      if (v == accurate_end(knob)) row = &t.rows.front();
      else
        for (const auto& candidate : t.rows)
          if (candidate.setting.knob == k && candidate.setting.value == v) row = &candidate;
      const bool safe = row->status == "ran" || row->status == "reference";
      const bool unsafe = row->status.rfind("failed", 0) == 0 || row->status.rfind("refused", 0) == 0;
      if (unsafe) {
        e.first_unsafe = v;
        e.why = row->status;
        break;
      }
      if (safe) e.last_safe = v;
    }
    t.edges.push_back(e);
  }
  return t;
}

void print_trade_table(std::ostream& out, const TradeTable& t) {
  const CompareTable& c = t.compare;
  fmt::print(out, "\nTrade: {} on seeds {} ({} seed{}); {}\n", c.config, fmt::join(c.seeds, ","), c.seeds.size(),
             c.seeds.size() == 1 ? "" : "s", t.rows.front().setting.label);
  std::size_t width = 8;
  for (const auto& r : t.rows) width = std::max(width, r.setting.label.size());
  width = std::min<std::size_t>(width, 40);
  fmt::print(out, "  {:<{}} {:>8} {:>8} {:>15} {:>15} {:>13}  {}\n", "setting", width, "push x", "total x", "d peak %",
             "d max c. %", "F(u) NRMS %", "status");
  for (const auto& r : t.rows) {
    const auto cells = row_cells(r, c.tolerance);
    fmt::print(out, "  {:<{}} {:>8} {:>8} {:>15} {:>15} {:>13}  {}\n", r.setting.label.substr(0, width), width, cells[0],
               cells[1], cells[2], cells[3], cells[4], cells[5]);
  }
  fmt::print(out, "  (differences from the reference setting, paired by seed: mean +- the 95 % Student-t half-width; "
                  "speedups: the reference's wall time over the setting's)\n\nStability edges\n");
  print_edges(out, t, "  ");
  if (c.revisions.size() > 1)
    fmt::print(out, "  note: the runs were computed by {} code revisions ({})\n", c.revisions.size(), fmt::join(c.revisions, ", "));
}

void write_trade_markdown(std::ostream& out, const TradeTable& t) {
  const CompareTable& c = t.compare;
  fmt::print(out, "# Trade: {} on seeds {}\n\nThe {}: every knob at its accurate end.\n\n", c.config,
             fmt::join(c.seeds, ","), t.rows.front().setting.label);
  fmt::print(out, "| setting | push speedup | total speedup | d peak (%) | d max contact (%) | F(u) NRMS (%) | status |\n");
  fmt::print(out, "|---|---|---|---|---|---|---|\n");
  for (const auto& r : t.rows) fmt::print(out, "| {} | {} |\n", r.setting.label, fmt::join(row_cells(r, c.tolerance), " | "));
  fmt::print(out, "\nDifferences from the reference setting, paired by seed: mean +- the half-width of the 95 % "
                  "Student-t interval over the seeds. Speedups: the reference's wall time over the setting's (push; "
                  "preparation from the shared deposition + push).\n\n## Stability edges\n\n");
  print_edges(out, t, "- ");
  if (c.revisions.size() > 1)
    fmt::print(out, "\nThe runs were computed by {} code revisions ({}).\n", c.revisions.size(), fmt::join(c.revisions, ", "));
}

void write_trade_csv(const fs::path& file, const TradeTable& t) {
  std::ofstream out(file);
  out << "knob,value,label,status,push_speedup,total_speedup,peak_diff,peak_diff_half_width,contact_diff,"
         "contact_diff_half_width,curve_nrms,seeds\n";
  const auto number = [](double v) { return std::isfinite(v) ? fmt::format("{:.10g}", v) : std::string(); };
  const auto quoted = [](std::string s) {
    for (auto& ch : s)
      if (ch == '"') ch = '\'';
    return "\"" + s + "\"";
  };
  for (const auto& r : t.rows) {
    fmt::print(out, "{},{},{},{}", r.setting.knob ? t.knob_names[*r.setting.knob] : "reference", r.setting.knob ? number(r.setting.value) : "", quoted(r.setting.label),
               quoted(r.status));
    if (r.measured) {
      const ModelRow& m = *r.measured;
      fmt::print(out, ",{},{},{},{},{},{},{},{}\n", number(m.push_speedup), number(m.total_speedup),
                 number(m.peak_force.difference.mean), number(m.peak_force.difference.half_width),
                 number(m.max_contact_force.difference.mean), number(m.max_contact_force.difference.half_width),
                 number(m.curve_difference.mean), m.seeds);
    } else {
      out << ",,,,,,,,0\n";
    }
  }
}

}  // namespace mfdem::campaigns
