// The cell-list neighbour search against the O(N^2) reference (dem::brute_force_pair_list):
// the same set of pairs (i, j, image of j), exactly, after sorting. Cases: random polydisperse
// packings in a walled box, with periodic axes (positions also given unwrapped, several box
// lengths away), elements far outside the walled box (clamped into the edge cells), and
// clump-like bodies of several elements, whose own pairs must be left out; two sizes 8x apart
// with many equal radii (a pair is found by its larger member).
#include <catch2/catch.hpp>
#include <omp.h>

#include <algorithm>
#include <random>
#include <tuple>
#include <vector>

#include "dem/neighbor_list.hpp"
#include "tests/dem/builders.hpp"

namespace {

using mfdem::dem::Domain;
using mfdem::dem::Elements;
using mfdem::dem::Index;
using mfdem::dem::PairList;
using mfdem::dem::Vec3;
using namespace mfdem::dem_test;

using Pair = std::tuple<Index, Index, int, int, int>;

std::vector<Pair> sorted_pairs(const PairList& list) {
  std::vector<Pair> out;
  for (Index p = 0; p < list.size(); ++p)
    out.emplace_back(list.first[p], list.second[p], list.image[p][0], list.image[p][1], list.image[p][2]);
  std::sort(out.begin(), out.end());
  return out;
}

struct Cloud {
  Elements elements;
  std::mt19937_64 rng;
  explicit Cloud(std::uint64_t seed) : rng(seed) {}
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
  }
  // Adds one element of its own body (body < 0) or of the given body.
  void add(const Vec3& x, double radius, Index body = -1) {
    elements.position.push_back(x);
    elements.offset.push_back(Vec3::Zero());
    elements.radius.push_back(radius);
    elements.material.push_back(0);
    elements.body.push_back(body < 0 ? static_cast<Index>(elements.body.size()) : body);
  }
  // `n` elements uniformly in [lo, hi], radii uniform in [r_min, r_max] (factor 4 apart).
  void scatter(int n, const Vec3& lo, const Vec3& hi, double r_min, double r_max) {
    for (int k = 0; k < n; ++k)
      add(Vec3(uniform(lo[0], hi[0]), uniform(lo[1], hi[1]), uniform(lo[2], hi[2])),
          uniform(r_min, r_max));
  }
};

// Compares the two searches and returns the number of pairs found.
std::size_t compare(const Elements& elements, const Domain& domain, double skin) {
  const auto cells = sorted_pairs(mfdem::dem::build_pair_list(elements, domain, skin));
  const auto brute = sorted_pairs(mfdem::dem::brute_force_pair_list(elements, domain, skin));
  CHECK(cells.size() == brute.size());
  CHECK(cells == brute);
  return brute.size();
}

const double kSkin = 0.004;  // m

}  // namespace

TEST_CASE("the cell list finds exactly the brute-force pairs in a walled box", "[dem][neighbours]") {
  Cloud cloud(11);
  // 1500 elements of radius 10-40 mm in a 0.6 m cube: a dense, strongly polydisperse cloud.
  cloud.scatter(1500, Vec3::Zero(), Vec3::Constant(0.6), 0.01, 0.04);
  const auto pairs = compare(cloud.elements, box_domain(Vec3::Zero(), Vec3::Constant(0.6)), kSkin);
  CHECK(pairs > 1000);
}

TEST_CASE("the cell list finds pairs of equal radii and of a radius 8x smaller, as brute force does",
          "[dem][neighbours]") {
  // A pair is found by its larger member, the higher index among equal radii: two sizes only
  // (many ties) and a graded bed's 4-32 mm spread check both branches, with a periodic axis.
  Cloud cloud(23);
  for (int k = 0; k < 1200; ++k)
    cloud.add(Vec3(cloud.uniform(0, 0.6), cloud.uniform(0, 0.6), cloud.uniform(0, 0.6)),
              k % 3 == 0 ? 0.032 : 0.004);
  const auto pairs = compare(cloud.elements, box_domain(Vec3::Zero(), Vec3::Constant(0.6), {false, true, false}), kSkin);
  CHECK(pairs > 300);
}

TEST_CASE("the cell list caps its grid in a large sparse box and still finds every pair", "[dem][neighbours]") {
  // 1 mm elements in a 100 m box would ask for 5e13 cells of one reach; the grid is capped at
  // about a million cells, and the pairs must still be exactly the brute-force ones.
  Cloud cloud(31);
  cloud.scatter(300, Vec3(10.0, 10.0, 10.0), Vec3(10.025, 10.025, 10.025), 0.001, 0.002);
  cloud.scatter(50, Vec3(90.0, 0.0, 0.0), Vec3(90.025, 0.025, 0.025), 0.001, 0.002);
  const auto pairs = compare(cloud.elements, box_domain(Vec3::Zero(), Vec3::Constant(100.0)), 0.0005);
  CHECK(pairs > 300);
}

TEST_CASE("the cell list finds exactly the brute-force pairs across periodic faces", "[dem][neighbours][periodic]") {
  const std::array<bool, 3> periodic = GENERATE(std::array<bool, 3>{true, false, false},
                                                std::array<bool, 3>{true, true, false},
                                                std::array<bool, 3>{true, true, true});
  Cloud cloud(12);
  // The solver integrates unwrapped positions between wraps, so elements may sit anywhere: here
  // up to two box lengths outside along the periodic axes. Pairs in the box and across faces.
  Vec3 lo = Vec3::Zero(), hi = Vec3::Constant(0.6);
  for (int a = 0; a < 3; ++a)
    if (periodic[a]) lo[a] = -1.2, hi[a] = 1.8;
  cloud.scatter(1500, Vec3::Zero(), Vec3::Constant(0.6), 0.01, 0.04);
  cloud.scatter(1500, lo, hi, 0.01, 0.04);
  const Domain domain = box_domain(Vec3::Zero(), Vec3::Constant(0.6), periodic);
  const auto pairs = compare(cloud.elements, domain, kSkin);
  CAPTURE(periodic[0], periodic[1], periodic[2]);
  CHECK(pairs > 2000);

  // Some pairs reach across a face (a non-zero image): the case the periodic search is for.
  const auto list = mfdem::dem::build_pair_list(cloud.elements, domain, kSkin);
  long long across = 0;
  for (const auto& image : list.image) across += image != mfdem::dem::Image{0, 0, 0};
  CHECK(across > 100);
}

TEST_CASE("the cell list works with the smallest periodic box it accepts (two reaches)", "[dem][neighbours][periodic]") {
  // Cutoff 2 x 0.04 + skin = 0.084 m; a box of 0.17 m is just over two reaches: a scan then meets
  // some cells twice, through two images, and must keep only the one in reach.
  const double edge = GENERATE(0.17, 0.19, 0.26);
  Cloud cloud(13);
  cloud.scatter(150, Vec3::Zero(), Vec3::Constant(edge), 0.01, 0.04);
  cloud.scatter(150, Vec3::Constant(-edge), Vec3::Constant(2.0 * edge), 0.01, 0.04);  // unwrapped
  const Domain domain = box_domain(Vec3::Zero(), Vec3::Constant(edge), {true, true, true});
  CAPTURE(edge);
  CHECK(compare(cloud.elements, domain, kSkin) > 300);
  // Below two reaches it is refused with a message that names the axis and the required length.
  const Domain too_small = box_domain(Vec3::Zero(), Vec3(0.16, edge, edge), {true, true, true});
  CHECK_THROWS_WITH(mfdem::dem::build_pair_list(cloud.elements, too_small, kSkin),
                    Catch::Matchers::Contains("periodic box length along axis x") &&
                        Catch::Matchers::Contains("must be at least 2 x (largest diameter + skin) = 0.16"));
}

TEST_CASE("the cell list clamps elements far outside a walled box into the edge cells without losing pairs",
          "[dem][neighbours]") {
  Cloud cloud(14);
  cloud.scatter(800, Vec3::Zero(), Vec3::Constant(0.6), 0.01, 0.04);
  // Clusters far outside on every side (escaped bodies, a sleeper above the bed): each cluster
  // is dense, so it has pairs of its own, and they all land in the clamped edge cells.
  const Vec3 centres[] = {Vec3(-5.0, 0.3, 0.3), Vec3(7.0, 0.3, 0.3), Vec3(0.3, -3.0, 0.3),
                          Vec3(0.3, 4.0, 0.3),  Vec3(0.3, 0.3, 20.0), Vec3(0.3, 0.3, -9.0),
                          Vec3(-5.0, -5.0, 20.0), Vec3(0.61, 0.3, 0.3)};
  for (const Vec3& c : centres) cloud.scatter(60, c - Vec3::Constant(0.1), c + Vec3::Constant(0.1), 0.01, 0.04);
  // And a column straddling the x+ wall plane, so in-box and clamped elements touch.
  cloud.scatter(100, Vec3(0.55, 0.0, 0.0), Vec3(0.7, 0.1, 0.6), 0.01, 0.04);
  const auto pairs = compare(cloud.elements, box_domain(Vec3::Zero(), Vec3::Constant(0.6)), kSkin);
  CHECK(pairs > 1000);
}

TEST_CASE("the cell list leaves out pairs of elements of the same body (clumps)", "[dem][neighbours]") {
  Cloud cloud(15);
  // Clump-like bodies: three overlapping elements per body, 0.3 radius apart.
  Index body = 0;
  for (int k = 0; k < 400; ++k, ++body) {
    const Vec3 c(cloud.uniform(0, 0.6), cloud.uniform(0, 0.6), cloud.uniform(0, 0.6));
    const double r = cloud.uniform(0.01, 0.03);
    for (int e = 0; e < 3; ++e) cloud.add(c + 0.3 * r * Vec3(e == 0, e == 1, e == 2), r, body);
  }
  const Domain walled = box_domain(Vec3::Zero(), Vec3::Constant(0.6));
  const Domain periodic = box_domain(Vec3::Zero(), Vec3::Constant(0.6), {true, true, true});
  const auto pairs = compare(cloud.elements, walled, kSkin);
  CHECK(pairs > 500);
  compare(cloud.elements, periodic, kSkin);
  for (const auto& [i, j, ix, iy, iz] : sorted_pairs(mfdem::dem::build_pair_list(cloud.elements, walled, kSkin)))
    CHECK(cloud.elements.body[i] != cloud.elements.body[j]);
  // Without the bodies (every element its own body), the 3 x 400 own pairs come back.
  Elements loose = cloud.elements;
  for (Index e = 0; e < loose.size(); ++e) loose.body[e] = e;
  CHECK(static_cast<std::size_t>(mfdem::dem::brute_force_pair_list(loose, walled, kSkin).size()) >= pairs + 3 * 400);
}

TEST_CASE("the cell list is the same list, in the same order, on one and two threads", "[dem][neighbours][threads]") {
  Cloud cloud(16);
  cloud.scatter(3000, Vec3(-0.3, 0.0, 0.0), Vec3(0.9, 0.6, 0.6), 0.01, 0.04);
  const Domain domain = box_domain(Vec3::Zero(), Vec3::Constant(0.6), {true, false, false});
  const int previous = omp_get_max_threads();
  omp_set_num_threads(1);
  const PairList one = mfdem::dem::build_pair_list(cloud.elements, domain, kSkin);
  omp_set_num_threads(2);
  const PairList two = mfdem::dem::build_pair_list(cloud.elements, domain, kSkin);
  omp_set_num_threads(previous);
  CHECK(one.first == two.first);
  CHECK(one.second == two.second);
  CHECK(one.image == two.image);
  CHECK(one.row_start == two.row_start);
  CHECK(one.as_second_pair == two.as_second_pair);
}
