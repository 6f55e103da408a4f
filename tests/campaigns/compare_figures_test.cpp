// The numbers behind compare's figures: the F(u) band over seeds and the section through the
// sleeper, on curves and files whose answer is known by construction.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "dem/hdf5_io.hpp"
#include "studies/campaigns/compare_figures.hpp"
#include "tests/support/temp_dir.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using mfdem::dem::Vec3;
namespace campaigns = mfdem::campaigns;
namespace h5 = mfdem::dem::h5;
namespace fs = std::filesystem;

TEST_CASE("curve band: the mean, lowest and highest of the seeds' F(u), on the shortest curve's range",
          "[campaigns][figures]") {
  // F = u on a fine grid to 5 mm and F = 3u on a coarse one to 4 mm: linear, so interpolation is exact.
  mfdem::railway::ForceCurve fine, coarse;
  for (int k = 0; k <= 500; ++k) fine.u.push_back(1e-5 * k), fine.force.push_back(1e-5 * k);
  for (int k = 0; k <= 40; ++k) coarse.u.push_back(1e-4 * k), coarse.force.push_back(3e-4 * k);
  const auto band = campaigns::curve_band("m", {fine, coarse}, 101);
  REQUIRE(band.u.size() == 101);
  CHECK(band.seeds == 2);
  CHECK_THAT(band.u.back(), WithinAbs(4e-3, 1e-15));
  for (std::size_t k = 0; k < band.u.size(); ++k) {
    CHECK_THAT(band.mean[k], WithinAbs(2.0 * band.u[k], 1e-12));
    CHECK_THAT(band.low[k], WithinAbs(band.u[k], 1e-12));
    CHECK_THAT(band.high[k], WithinAbs(3.0 * band.u[k], 1e-12));
  }
  // One seed: the band is the curve itself.
  const auto alone = campaigns::curve_band("m", {fine}, 11);
  for (std::size_t k = 0; k < alone.u.size(); ++k) {
    CHECK(alone.low[k] == alone.mean[k]);
    CHECK(alone.high[k] == alone.mean[k]);
  }
  CHECK(campaigns::curve_band("m", {}).u.empty());
}

namespace {

// A push.h5 and packing.h5 holding only what the section reads.
struct Stone {
  Vec3 position, displacement;
  double size;
};
struct Contact {
  int a, b;
  Vec3 point, force;
};

campaigns::RunFiles write_run(const fs::path& folder, const std::string& model, const std::vector<Stone>& stones,
                              const std::vector<Contact>& contacts) {
  fs::create_directories(folder);
  const campaigns::RunFiles files{model, folder / "push.h5", folder / "packing.h5"};
  std::vector<Vec3> position, displacement, point, force;
  std::vector<mfdem::dem::Index> a, b;
  std::vector<double> size;
  for (const auto& s : stones) position.push_back(s.position), displacement.push_back(s.displacement), size.push_back(s.size);
  for (const auto& c : contacts) a.push_back(c.a), b.push_back(c.b), point.push_back(c.point), force.push_back(c.force);
  hid_t file = H5Fcreate(files.push.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  h5::write_vec3s(file, "end_state/position", position);
  h5::write_vec3s(file, "end_state/displacement", displacement);
  h5::write_vec3s(file, "end_state/contact_point", point);
  h5::write_vec3s(file, "end_state/contact_force", force);
  h5::write_ints(file, "end_state/contact_body_a", a);
  h5::write_ints(file, "end_state/contact_body_b", b);
  h5::write_doubles(file, "curve/u", std::vector<double>{0.0, 0.005});
  h5::write_doubles(file, "curve/heave", std::vector<double>{0.0, 0.001});
  H5Fclose(file);
  file = H5Fcreate(files.packing.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t g = h5::make_group(file, "packing");
  // A sleeper 0.6 m long (x), 0.26 m wide (y), 0.21 m high, centred at (0, 0, 0.405).
  for (const auto& [name, value] : {std::pair{"sleeper_centre_x", 0.0}, {"sleeper_centre_y", 0.0},
                                    {"sleeper_centre_z", 0.405}, {"sleeper_half_extent_x", 0.3},
                                    {"sleeper_half_extent_y", 0.13}, {"sleeper_half_extent_z", 0.105},
                                    {"domain_max_x", 2.0}})
    h5::write_attribute(g, name, value);
  h5::write_doubles(g, "size", size);
  H5Gclose(g);
  H5Fclose(file);
  return files;
}

}  // namespace

TEST_CASE("section views: the stones and chains in the slab through the sleeper, one clip and one threshold",
          "[campaigns][figures]") {
  const mfdem::test::TempDir dir;
  // Stone sizes 0.04 and 0.06: the slab is |y| <= 0.03. Stone 0 and 1 in it, 2 outside (y = 0.05),
  // 3 in it but behind the region (x < -0.3 - 0.1), 4 the farthest ahead (x = 1.2, sets x_max).
  const std::vector<Stone> reference_stones = {
      {{0.0, 0.01, 0.1}, {0.001, 0.0, 0.0}, 0.04},  {{0.35, -0.03, 0.2}, {0.004, 0.0, 0.003}, 0.06},
      {{0.2, 0.05, 0.1}, {0.010, 0.0, 0.0}, 0.04},  {{-0.5, 0.0, 0.1}, {0.0, 0.0, 0.0}, 0.04},
      {{1.2, 0.0, 0.05}, {0.002, 0.0, 0.0}, 0.06}};
  // Forces 30 N (in the slab), 10 N (in it, below the mean 20 N), 20 N (out of the slab).
  const std::vector<Contact> reference_contacts = {{0, 1, {0.2, 0.0, 0.15}, {0.0, 0.0, 30.0}},
                                                   {0, 4, {0.6, 0.0, 0.07}, {10.0, 0.0, 0.0}},
                                                   {1, 2, {0.3, 0.04, 0.15}, {0.0, 20.0, 0.0}}};
  // A second model: the same bed, every displacement doubled, the weak contact at 40 N.
  std::vector<Stone> model_stones = reference_stones;
  for (auto& s : model_stones) s.displacement *= 2.0;
  std::vector<Contact> model_contacts = reference_contacts;
  model_contacts[1].force = {40.0, 0.0, 0.0};
  const auto sections = campaigns::section_views(
      7, {write_run(dir.path() / "r", "ref", reference_stones, reference_contacts),
          write_run(dir.path() / "m", "model", model_stones, model_contacts)});

  CHECK(sections.seed == 7);
  CHECK_THAT(sections.slab_half_width, WithinAbs(0.03, 1e-15));
  CHECK_THAT(sections.x_min, WithinAbs(-0.4, 1e-15));
  CHECK_THAT(sections.x_max, WithinAbs(1.2 + 0.03 + 0.02, 1e-12));  // the toe stone, its half size, 20 mm
  CHECK_THAT(sections.z_max, WithinAbs(0.51 + 0.05, 1e-12));
  CHECK_THAT(sections.sleeper_x0, WithinAbs(-0.3 + 0.005, 1e-15));  // moved by u_end
  CHECK_THAT(sections.sleeper_z1, WithinAbs(0.51 + 0.001, 1e-15));  // and by the heave
  CHECK_THAT(sections.chain_threshold, WithinAbs(20.0, 1e-12));     // the reference's mean
  REQUIRE(sections.models.size() == 2);
  const auto& ref = sections.models[0];
  CHECK(ref.model == "ref");
  REQUIRE(ref.x.size() == 3);  // stones 0, 1 and 4
  CHECK(ref.x == std::vector<double>{0.0, 0.35, 1.2});
  CHECK(ref.radius == std::vector<double>{0.02, 0.03, 0.03});
  CHECK_THAT(ref.displacement[1], WithinAbs(0.005, 1e-15));
  REQUIRE(ref.force.size() == 1);  // the 30 N chain only
  CHECK(ref.force[0] == 30.0);
  CHECK(ref.x2[0] == 0.35);
  const auto& model = sections.models[1];
  CHECK(model.force.size() == 2);  // the 40 N contact now passes the reference's threshold
  CHECK(sections.largest_chain_force == 40.0);
  // One clip over both panels: the 98th percentile (nearest rank) of the six slab displacements
  // {1, 5, 2, 2, 10, 4} mm is the largest, 10 mm.
  CHECK_THAT(sections.displacement_clip, WithinAbs(0.010, 1e-15));

  // Written and readable: the reference's panel first.
  const fs::path data = dir.path() / "figures.h5";
  campaigns::write_figure_data(data, {"test", 2, 0.05}, {campaigns::curve_band("ref", {})}, sections);
  CHECK_FALSE(fs::exists(dir.path() / "figures.h5.partial"));
  const hid_t file = H5Fopen(data.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  CHECK(h5::read_doubles(file, "section/00/x") == ref.x);
  CHECK(h5::read_doubles(file, "section/01/force").size() == 2);
  CHECK(h5::read_text_attribute(file, "config") == "test");
  H5Fclose(file);
}

TEST_CASE("section views refuse a run without its end state, naming the file", "[campaigns][figures]") {
  const mfdem::test::TempDir dir;
  const auto files = write_run(dir.path() / "r", "ref", {{{0, 0, 0.1}, {0, 0, 0}, 0.04}}, {});
  fs::remove(files.push);
  const hid_t file = H5Fcreate(files.push.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  h5::write_doubles(file, "curve/u", std::vector<double>{0.0});
  H5Fclose(file);
  CHECK_THROWS_WITH(campaigns::section_views(1, {files}), Contains(files.push.string()) && Contains("end_state"));
}
