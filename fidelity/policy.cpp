#include "fidelity/policy.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <cmath>

namespace mfdem::fidelity {
namespace {

std::string number_text(double v) { return fmt::format("{:g}", v); }

// NAME or NAME:key=value,key=value: how a policy is written and described.
std::string spec_text(const std::string& name, const std::vector<PolicyParameter>& parameters) {
  std::string out = name;
  for (std::size_t k = 0; k < parameters.size(); ++k)
    out += (k == 0 ? ":" : ",") + parameters[k].name + "=" + number_text(parameters[k].value);
  return out;
}

const PolicyParameter* find_parameter(const PolicySpec& spec, std::string_view name) {
  for (const auto& p : spec.parameters)
    if (p.name == name) return &p;
  return nullptr;
}

void require_none(const PolicySpec& spec) {
  if (!spec.parameters.empty())
    throw PolicyError(spec.parameters.front().name,
                      fmt::format("policy '{}' takes no parameters (got {}={})", spec.name,
                                  spec.parameters.front().name, number_text(spec.parameters.front().value)));
}

Policy constant_policy(const std::string& name, Representation r) {
  return {name, {}, [r](const StoneGeometry&) { return r; }};
}

Policy layer_by_height(const PolicySpec& spec, const BedScale& scale) {
  const PolicyParameter* h = find_parameter(spec, "h");
  const PolicyParameter* fraction = find_parameter(spec, "h_fraction");
  if (!h && !fraction)
    throw PolicyError("h", "policy 'layer-by-height' needs h (m above the floor) or h_fraction (of the depth "
                           "from the floor to the sleeper base), e.g. layer-by-height:h=0.15");
  if (h && fraction)
    throw PolicyError("h_fraction", "policy 'layer-by-height' takes h or h_fraction, not both");
  if (!(scale.sleeper_base > 0.0))
    throw PolicyError("h", fmt::format("the sleeper base lies at {} m, not above the floor", scale.sleeper_base));
  const double height = h ? h->value : fraction->value * scale.sleeper_base;
  if (h && (height < 0.0 || height > scale.sleeper_base))
    throw PolicyError("h", fmt::format("h = {}: expected a layer height in m from 0 (the floor) to {} (the "
                                       "sleeper base)", number_text(height), number_text(scale.sleeper_base)));
  if (fraction && (fraction->value < 0.0 || fraction->value > 1.0))
    throw PolicyError("h_fraction", fmt::format("h_fraction = {}: expected a fraction from 0 (the floor) to 1 (the "
                                                "sleeper base, {} m)", number_text(fraction->value),
                                                number_text(scale.sleeper_base)));
  return {"layer-by-height",
          {{"h", height}, {"h_fraction", height / scale.sleeper_base}},
          [height](const StoneGeometry& s) { return s.height < height ? Representation::ball : Representation::clump; }};
}

Policy zone_by_distance(const PolicySpec& spec, const BedScale&) {
  const PolicyParameter* d = find_parameter(spec, "d");
  if (!d)
    throw PolicyError("d", "policy 'zone-by-distance' needs d, the distance in m from the sleeper's surface "
                           "within which stones stay clumps, e.g. zone-by-distance:d=0.05");
  if (d->value < 0.0)
    throw PolicyError("d", fmt::format("d = {}: expected a distance in m >= 0", number_text(d->value)));
  const double distance = d->value;
  return {"zone-by-distance",
          {{"d", distance}},
          [distance](const StoneGeometry& s) {
            return s.sleeper_gap <= distance ? Representation::clump : Representation::ball;
          }};
}

PolicyRegistry make_builtin() {
  PolicyRegistry r;
  r.add({"all-clump", "every stone a clump (the reference model)", {}, [](const PolicySpec& s, const BedScale&) {
           require_none(s);
           return constant_policy("all-clump", Representation::clump);
         }});
  r.add({"all-ball", "every stone a ball", {}, [](const PolicySpec& s, const BedScale&) {
           require_none(s);
           return constant_policy("all-ball", Representation::ball);
         }});
  r.add({"layer-by-height", "stones with their centre below h (m above the floor) become balls",
         {"h", "h_fraction"}, layer_by_height});
  r.add({"zone-by-distance", "stones farther than d (m) from the sleeper's surface become balls", {"d"},
         zone_by_distance});
  return r;
}

}  // namespace

Representation representation_named(std::string_view name) {
  if (name == "clump") return Representation::clump;
  if (name == "ball") return Representation::ball;
  throw std::invalid_argument(fmt::format("representation '{}': expected clump or ball", name));
}

std::string Policy::describe() const { return spec_text(name, parameters); }

double Policy::parameter(std::string_view wanted) const {
  for (const auto& p : parameters)
    if (p.name == wanted) return p.value;
  throw std::out_of_range(fmt::format("policy '{}' has no parameter '{}'", name, wanted));
}

std::string PolicySpec::text() const { return spec_text(name, parameters); }

PolicySpec parse_policy_spec(std::string_view text) {
  PolicySpec spec;
  const std::size_t colon = text.find(':');
  spec.name = std::string(text.substr(0, colon));
  if (spec.name.empty()) throw PolicyError("", "expected a policy name, e.g. layer-by-height:h=0.15");
  if (colon == std::string_view::npos) return spec;
  std::string_view rest = text.substr(colon + 1);
  while (true) {
    const std::size_t comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    const std::size_t equals = item.find('=');
    if (equals == std::string_view::npos || equals == 0)
      throw PolicyError("", fmt::format("'{}': expected key=value after the policy name", item));
    PolicyParameter p;
    p.name = std::string(item.substr(0, equals));
    const std::string_view value = item.substr(equals + 1);
    const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), p.value);
    if (error != std::errc() || end != value.data() + value.size() || !std::isfinite(p.value))
      throw PolicyError(p.name, fmt::format("{} = '{}': expected a finite number", p.name, value));
    if (find_parameter(spec, p.name)) throw PolicyError(p.name, fmt::format("{} is given twice", p.name));
    spec.parameters.push_back(std::move(p));
    if (comma == std::string_view::npos) break;
    rest = rest.substr(comma + 1);
  }
  return spec;
}

PolicyRegistry& PolicyRegistry::builtin() {
  static PolicyRegistry registry = make_builtin();
  return registry;
}

void PolicyRegistry::add(PolicyKind kind) {
  if (std::any_of(kinds_.begin(), kinds_.end(), [&](const PolicyKind& k) { return k.name == kind.name; }))
    throw std::invalid_argument(fmt::format("fidelity policy '{}' is registered twice", kind.name));
  kinds_.push_back(std::move(kind));
}

void PolicyRegistry::add(const std::string& name, const std::string& summary, StonePredicate choose) {
  add({name, summary, {}, [name, choose](const PolicySpec& s, const BedScale&) {
         require_none(s);
         return Policy{name, {}, choose};
       }});
}

Policy PolicyRegistry::make(const PolicySpec& spec, const BedScale& scale) const {
  const auto kind = std::find_if(kinds_.begin(), kinds_.end(), [&](const PolicyKind& k) { return k.name == spec.name; });
  if (kind == kinds_.end())
    throw PolicyError("", fmt::format("unknown fidelity policy '{}'; expected one of: {}", spec.name, listing()));
  for (const auto& p : spec.parameters)
    if (std::find(kind->parameters.begin(), kind->parameters.end(), p.name) == kind->parameters.end())
      throw PolicyError(p.name, kind->parameters.empty()
                                    ? fmt::format("policy '{}' takes no parameters (got {})", spec.name, p.name)
                                    : fmt::format("policy '{}' has no parameter '{}'; expected {}", spec.name, p.name,
                                                  fmt::join(kind->parameters, " or ")));
  return kind->make(spec, scale);
}

std::string PolicyRegistry::listing() const {
  std::string out;
  for (const auto& k : kinds_) {
    out += (out.empty() ? "" : ", ") + k.name;
    if (!k.parameters.empty()) out += fmt::format(" ({})", fmt::join(k.parameters, " or "));
  }
  return out;
}

}  // namespace mfdem::fidelity
