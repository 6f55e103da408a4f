#include "fidelity/template_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "fidelity/shape_error.hpp"

namespace mfdem::fidelity {

namespace {

constexpr std::string_view format_name = "mfdem clump template 1";

// Shortest text that reads back as the same double (fmt prints the round-trip form).
std::string number(double x) { return fmt::format("{}", x); }
std::string vec(const Vec3& v) { return fmt::format("[{}, {}, {}]", number(v.x()), number(v.y()), number(v.z())); }

std::string rule_name(BubblePackRule rule) {
  return rule == BubblePackRule::largest_new_volume ? "largest_new_volume" : "farthest_point";
}

// Typed access to one table of the file, with messages naming file, line and dotted key.
class Table {
 public:
  Table(const toml::table& table, std::string path, std::string_view source)
      : table_(table), path_(std::move(path)), source_(source) {}

  [[noreturn]] void fail(std::string_view key, std::string_view problem) const {
    const toml::node* node = table_.get(key);
    const auto line = node ? node->source().begin.line : table_.source().begin.line;
    throw ShapeError(fmt::format("{}:{}: {}: {}", source_, line, dotted(key), problem));
  }
  const toml::node& node(std::string_view key, std::string_view expected) const {
    const toml::node* node = table_.get(key);
    if (!node) {
      const auto line = table_.source().begin.line;
      throw ShapeError(fmt::format("{}:{}: {} is missing; expected {}", source_, line, dotted(key), expected));
    }
    return *node;
  }
  Table table(std::string_view key) const {
    const toml::table* sub = node(key, "a table").as_table();
    if (!sub) fail(key, "expected a table");
    return Table(*sub, dotted(key), source_);
  }
  bool has(std::string_view key) const { return table_.contains(key); }
  std::string text(std::string_view key) const {
    const auto value = node(key, "a string").value<std::string>();
    if (!value) fail(key, "expected a string");
    return *value;
  }
  double real(std::string_view key) const { return real_of(node(key, "a number"), key); }
  bool boolean(std::string_view key) const {
    const auto value = node(key, "true or false").value<bool>();
    if (!value) fail(key, "expected true or false");
    return *value;
  }
  long long integer(std::string_view key) const {
    const auto value = node(key, "an integer").value<long long>();
    if (!value || !node(key, "").is_integer()) fail(key, "expected an integer");
    return *value;
  }
  std::vector<double> reals(std::string_view key, std::size_t size) const {
    const toml::array* array = node(key, "an array of numbers").as_array();
    if (!array || (size && array->size() != size))
      fail(key, size ? fmt::format("expected an array of {} numbers", size) : "expected an array of numbers");
    std::vector<double> values;
    for (const auto& element : *array) values.push_back(real_of(element, key));
    return values;
  }
  Vec3 vec3(std::string_view key) const {
    const auto v = reals(key, 3);
    return Vec3(v[0], v[1], v[2]);
  }
  // An array of arrays of `width` numbers.
  std::vector<std::vector<double>> rows(std::string_view key, std::size_t width) const {
    const toml::array* array = node(key, "an array of arrays").as_array();
    if (!array) fail(key, fmt::format("expected an array of arrays of {} numbers", width));
    std::vector<std::vector<double>> result;
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::array* row = (*array)[i].as_array();
      if (!row || row->size() != width)
        fail(key, fmt::format("row {} is not an array of {} numbers", i + 1, width));
      std::vector<double> values;
      for (const auto& element : *row) values.push_back(real_of(element, key));
      result.push_back(std::move(values));
    }
    return result;
  }

 private:
  double real_of(const toml::node& node, std::string_view key) const {
    const auto value = node.value<double>();
    if (!value || !(node.is_floating_point() || node.is_integer())) fail(key, "expected a number");
    if (!std::isfinite(*value)) fail(key, "numbers must be finite");
    return *value;
  }
  std::string dotted(std::string_view key) const { return path_.empty() ? std::string(key) : path_ + "." + std::string(key); }

  const toml::table& table_;
  std::string path_;
  std::string_view source_;
};

ShapeSource read_source(const Table& t) {
  ShapeSource source;
  const std::string kind = t.text("kind");
  if (kind == "generated") {
    source.kind = ShapeSource::Kind::generated;
    const long long seed = t.integer("seed");
    if (seed < 0 || seed > 0xffffffffLL) t.fail("seed", fmt::format("expected a seed from 0 to 4294967295 (got {})", seed));
    source.stone.seed = static_cast<std::uint32_t>(seed);
    source.stone.elongation = t.real("elongation");
    source.stone.flatness = t.real("flatness");
    source.stone.vertices = static_cast<int>(t.integer("vertices"));
  } else if (kind == "stl") {
    source.kind = ShapeSource::Kind::stl;
    source.stl_file = t.text("stl");
  } else {
    t.fail("kind", fmt::format("expected \"generated\" or \"stl\" (got \"{}\")", kind));
  }
  source.packing.pebbles = static_cast<int>(t.integer("pebbles"));
  source.packing.min_radius = t.real("min_radius");
  source.packing.grid_cells = static_cast<int>(t.integer("grid_cells"));
  const std::string rule = t.text("rule");
  if (rule == "largest_new_volume") source.packing.rule = BubblePackRule::largest_new_volume;
  else if (rule == "farthest_point") source.packing.rule = BubblePackRule::farthest_point;
  else t.fail("rule", fmt::format("expected \"largest_new_volume\" or \"farthest_point\" (got \"{}\")", rule));
  source.match_volume = t.boolean("match_volume");
  return source;
}

}  // namespace

std::string format_template(const ClumpTemplate& clump) {
  std::string out = fmt::format(
      "# Clump template '{}' of mfdem. Generated: rebuild it (mfdem shapes build) rather than edit it.\n"
      "# Body frame: origin at the clump's centre of mass, axes along its principal axes (ascending moments).\n"
      "# Lengths in units of the stone's size d (its intermediate dimension); for density rho:\n"
      "# mass = rho volume d^3, principal moments = rho principal_inertia d^5.\n"
      "format = \"{}\"\nname = \"{}\"\n",
      clump.name, format_name, clump.name);
  if (clump.source) {
    const ShapeSource& s = *clump.source;
    out += "\n[source]  # the settings that regenerate this template\n";
    if (s.kind == ShapeSource::Kind::generated)
      out += fmt::format("kind = \"generated\"\nseed = {}\nelongation = {}\nflatness = {}\nvertices = {}\n", s.stone.seed,
                         number(s.stone.elongation), number(s.stone.flatness), s.stone.vertices);
    else
      out += fmt::format("kind = \"stl\"\nstl = \"{}\"\n", s.stl_file);
    out += fmt::format("pebbles = {}\nmin_radius = {}\ngrid_cells = {}\nrule = \"{}\"\nmatch_volume = {}\n",
                       s.packing.pebbles, number(s.packing.min_radius), s.packing.grid_cells, rule_name(s.packing.rule),
                       s.match_volume);
  }
  const Quat& q = clump.input_to_principal;
  out += fmt::format(
      "\n[clump]\nvolume = {}\nprincipal_inertia = {}  # per unit density\ncentre_of_mass_input = {}  # input units\n"
      "input_to_principal = [{}, {}, {}, {}]  # quaternion w, x, y, z\ninput_size = {}  # d in input units\n"
      "pebbles = [  # x, y, z, radius\n",
      number(clump.volume), vec(clump.principal_inertia), vec(clump.centre_of_mass_input), number(q.w()), number(q.x()),
      number(q.y()), number(q.z()), number(clump.input_size));
  for (const auto& p : clump.pebbles)
    out += fmt::format("  [{}, {}, {}, {}],\n", number(p.centre.x()), number(p.centre.y()), number(p.centre.z()),
                       number(p.radius));
  out += "]\n";
  const auto& in = clump.integration;
  out += fmt::format(
      "\n[integration]  # Sobol integration of the union: estimated relative errors\nvolume_error = {}\n"
      "centroid_error = {}\ninertia_error = {}\npoints = {}\n",
      number(in.volume_error), number(in.centroid_error), number(in.inertia_error), in.points);
  if (clump.fit) {
    const SurfaceFit& f = *clump.fit;
    out += fmt::format(
        "\n[surface]  # the stone's surface in the body frame, and how well the clump fits it\n"
        "volume = {}\ncentroid = {}\ninertia = [{}, {}, {}]  # per unit density, about the centroid\n"
        "length = {}\nintermediate = {}\nthickness = {}\n"
        "volume_error = {}  # (clump - surface) / surface\ninertia_error = {}  # Frobenius norm, relative\n"
        "protrusion = {}  # how far pebbles reach outside the surface, at most\nvertices = [\n",
        number(f.volume), vec(f.centroid), vec(f.inertia.row(0).transpose()), vec(f.inertia.row(1).transpose()), vec(f.inertia.row(2).transpose()),
        number(f.indices.length), number(f.indices.intermediate), number(f.indices.thickness), number(f.volume_error),
        number(f.inertia_error), number(f.protrusion));
    for (const auto& v : f.surface.vertices) out += fmt::format("  {},\n", vec(v));
    out += "]\ntriangles = [\n";
    for (const auto& t : f.surface.triangles) out += fmt::format("  [{}, {}, {}],\n", t[0], t[1], t[2]);
    out += "]\n";
  }
  return out;
}

void save_template(const ClumpTemplate& clump, const std::filesystem::path& file) {
  std::ofstream out(file, std::ios::binary);
  const std::string text = format_template(clump);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) throw ShapeError(fmt::format("{}: cannot be written", file.string()));
}

ClumpTemplate parse_template(std::string_view text, std::string_view source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& error) {
    throw ShapeError(fmt::format("{}:{}: not valid TOML: {}", source, error.source().begin.line, error.description()));
  }
  const Table top(root, "", source);
  if (const std::string format = top.text("format"); format != format_name)
    top.fail("format", fmt::format("expected \"{}\" (got \"{}\")", format_name, format));

  ClumpTemplate clump;
  clump.name = top.text("name");
  if (top.has("source")) clump.source = read_source(top.table("source"));

  const Table c = top.table("clump");
  clump.volume = c.real("volume");
  if (!(clump.volume > 0.0)) c.fail("volume", "expected a positive volume");
  clump.principal_inertia = c.vec3("principal_inertia");
  if (!(clump.principal_inertia.array() > 0.0).all()) c.fail("principal_inertia", "expected three positive moments");
  clump.centre_of_mass_input = c.vec3("centre_of_mass_input");
  const auto q = c.reals("input_to_principal", 4);
  clump.input_to_principal = Quat(q[0], q[1], q[2], q[3]);
  if (std::abs(clump.input_to_principal.norm() - 1.0) > 1e-9)
    c.fail("input_to_principal", "expected a unit quaternion [w, x, y, z]");
  clump.input_size = c.real("input_size");
  if (!(clump.input_size > 0.0)) c.fail("input_size", "expected a positive size");
  for (const auto& row : c.rows("pebbles", 4)) {
    if (!(row[3] > 0.0)) c.fail("pebbles", fmt::format("pebble {} has radius {}; radii must be positive", clump.pebbles.size() + 1, row[3]));
    clump.pebbles.push_back({Vec3(row[0], row[1], row[2]), row[3]});
  }
  if (clump.pebbles.empty()) c.fail("pebbles", "expected at least one pebble");

  const Table in = top.table("integration");
  clump.integration.volume_error = in.real("volume_error");
  clump.integration.centroid_error = in.real("centroid_error");
  clump.integration.inertia_error = in.real("inertia_error");
  clump.integration.points = in.integer("points");
  clump.integration.properties.volume = clump.volume;
  clump.integration.properties.inertia = clump.principal_inertia.asDiagonal();

  if (top.has("surface")) {
    const Table s = top.table("surface");
    SurfaceFit fit;
    fit.volume = s.real("volume");
    fit.centroid = s.vec3("centroid");
    const auto inertia = s.rows("inertia", 3);
    if (inertia.size() != 3) s.fail("inertia", "expected 3 rows of 3 numbers");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) fit.inertia(i, j) = inertia[i][j];
    fit.indices = {s.real("length"), s.real("intermediate"), s.real("thickness")};
    fit.volume_error = s.real("volume_error");
    fit.inertia_error = s.real("inertia_error");
    fit.protrusion = s.real("protrusion");
    for (const auto& v : s.rows("vertices", 3)) fit.surface.vertices.push_back(Vec3(v[0], v[1], v[2]));
    for (const auto& t : s.rows("triangles", 3)) {
      std::array<int, 3> tri;
      for (int k = 0; k < 3; ++k) {
        if (t[k] != std::floor(t[k])) s.fail("triangles", "expected vertex numbers (integers)");
        tri[k] = static_cast<int>(t[k]);
      }
      fit.surface.triangles.push_back(tri);
    }
    check_closed(fit.surface, fmt::format("{}: surface", source));
    clump.fit = std::move(fit);
  }
  return clump;
}

ClumpTemplate load_template(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ShapeError(fmt::format("{}: cannot be opened (check the path); expected a clump template", file.string()));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_template(text.str(), file.string());
}

}  // namespace mfdem::fidelity
