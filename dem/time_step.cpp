#include "dem/time_step.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mfdem::dem {
namespace {

// Per material: the lightest body, its inverse rotational lever and inverse inertia.
struct Lightest {
  bool present = false;
  double inverse_mass = 0.0;              // 1/m, 1/kg
  double inverse_tangential_mass = 0.0;   // 1/m + r^2/I
  double radius = 0.0;                    // largest element radius
  bool spheres_only = true;               // every body a sphere: its lever along the contact normal
  Index bodies = 0, last_body = -1;       // bodies with elements of the material (elements of a body are contiguous)
  // Per partner (a material's index, or the number of materials for a wall): the largest of the
  // rolling spring's share Rbar^2 / I_min and of its coupling Rbar |lever| / I_min over the
  // elements, Rbar = r r' / (r + r') taken with the partner's largest radius r' (r on a wall). Per
  // element, not the largest radius with the lightest inertia: on a graded bed (radii 1:4) that
  // pairing overstated the rolling mode 3.7-fold.
  std::vector<double> rolling_share, rolling_coupling;
};

double damped_factor(double beta) { return std::sqrt(1.0 + beta * beta) - beta; }

}  // namespace

TimeStepLimit critical_time_step(const Bodies& bodies, const Elements& elements,
                                 const MaterialTable& materials,
                                 const std::vector<PlaneWall>& walls) {
  const int nm = materials.size();
  std::vector<Lightest> light(nm);
  // First each material's largest radius: a contact's Rbar below takes the partner's.
  for (Index e = 0; e < elements.size(); ++e) {
    Lightest& l = light[elements.material[e]];
    l.present = true;
    l.radius = std::max(l.radius, elements.radius[e]);
  }
  for (Lightest& l : light) l.rolling_share.assign(nm + 1, 0.0), l.rolling_coupling.assign(nm + 1, 0.0);
  for (Index e = 0; e < elements.size(); ++e) {
    const Index b = elements.body[e];
    const int m = elements.material[e];
    const double r = elements.radius[e];
    const double inv_mass = 1.0 / bodies.mass[b];
    const double inv_inertia = 1.0 / bodies.inertia[b].minCoeff();
    // A tangential impulse t at lever r turns the body by I^-1 (r x t); its inverse mass is
    // 1/m + (r x t).I^-1.(r x t). Two bounds, the smaller kept: |r|^2 / I_min (exact for a
    // sphere), and sum_k (a_i^2 + a_j^2) / I_k with a = |offset| + radius per body axis (tight
    // for a long clump, whose far pebbles turn it about its stiff axes, not its long one).
    const double lever = r + elements.offset[e].norm();
    const Vec3 reach = elements.offset[e].cwiseAbs() + Vec3::Constant(r);
    const Vec3& inertia = bodies.inertia[b];
    const double by_axes = (reach[1] * reach[1] + reach[2] * reach[2]) / inertia[0] +
                           (reach[0] * reach[0] + reach[2] * reach[2]) / inertia[1] +
                           (reach[0] * reach[0] + reach[1] * reach[1]) / inertia[2];
    const double turning = std::min(lever * lever * inv_inertia, by_axes);
    Lightest& l = light[m];
    if (b != l.last_body) ++l.bodies, l.last_body = b;
    l.inverse_mass = std::max(l.inverse_mass, inv_mass);
    l.inverse_tangential_mass =
        std::max(l.inverse_tangential_mass, inv_mass + turning);
    if (!elements.offset[e].isZero() || inertia.maxCoeff() != inertia.minCoeff()) l.spheres_only = false;
    for (int partner = 0; partner <= nm; ++partner) {
      if (partner < nm && !light[partner].present) continue;
      const double rbar = partner < nm ? r * light[partner].radius / (r + light[partner].radius) : r;
      l.rolling_share[partner] = std::max(l.rolling_share[partner], rbar * rbar * inv_inertia);
      l.rolling_coupling[partner] = std::max(l.rolling_coupling[partner], rbar * lever * inv_inertia);
    }
  }

  TimeStepLimit best{std::numeric_limits<double>::infinity(), "no contacts possible"};
  TimeStepLimit fallback = best;
  // Lowers `into` to the limit of a mode of squared frequency omega2 when that is smaller.
  auto consider = [](TimeStepLimit& into, double omega2, double beta, const std::string& what) {
    if (omega2 <= 0.0) return;
    const double dt = 2.0 / std::sqrt(omega2) * damped_factor(beta);
    if (dt < into.limit) into = {dt, what};
  };
  auto consider_pair = [&](TimeStepLimit& into, const PairParameters& p, int ma, int mb, const std::string& label) {
    // mb == nm: a wall (infinite mass, no rotation).
    const Lightest& a = light[ma];
    const Lightest* b = mb < nm ? &light[mb] : nullptr;
    const double inv_m = a.inverse_mass + (b ? b->inverse_mass : 0.0);
    const double inv_mt = a.inverse_tangential_mass + (b ? b->inverse_tangential_mass : 0.0);
    consider(into, p.normal_stiffness * inv_m, p.damping_ratio,
             fmt::format("normal spring of {} (kn = {:.3g} N/m, lightest m_eff = {:.3g} kg)",
                         label, p.normal_stiffness, 1.0 / inv_m));
    consider(into, p.shear_stiffness * inv_mt, p.damping_ratio,
             fmt::format("shear spring of {} (ks = {:.3g} N/m)", label, p.shear_stiffness));
    // Shear and rolling springs both turn the bodies, so they couple. In the scaled coordinates
    // M^-1/2 x the pair's stiffness is ks s s^T + kr t t^T (s the shear spring's direction, t the
    // rolling spring's, kr = ks Rbar^2), whose largest eigenvalue is that of the 2 x 2 matrix
    // [[A, C], [C, B]]: A = ks s.s (the shear mode), B = kr t.t (the rolling mode),
    // C = sqrt(ks kr) s.t. B = ks (Rbar^2 / I_a + Rbar^2 / I_b) is bounded by the two materials'
    // rolling shares. For spheres C = ks Rbar (r_b / I_b - r_a / I_a) (both spin the contact the
    // same way, the rolling spring takes their difference), so |C| <= ks max(Rbar r / I), the
    // larger rolling coupling, and 0 for equal spheres: the two modes hardly couple. For clumps
    // only |C| <= sqrt(A B) is known, which gives A + B. The eigenvalue grows with A, B and |C|, so
    // these bounds over the elements bound every pair of the materials.
    if (p.rolling_friction > 0.0) {
      const double shear_mode = p.shear_stiffness * inv_mt;
      const double rolling_mode = p.shear_stiffness * (a.rolling_share[mb] + (b ? b->rolling_share[ma] : 0.0));
      double coupled = shear_mode + rolling_mode;
      if (a.spheres_only && (!b || b->spheres_only)) {
        const double cross = p.shear_stiffness * std::max(a.rolling_coupling[mb], b ? b->rolling_coupling[ma] : 0.0);
        const double gap = shear_mode - rolling_mode;
        coupled = 0.5 * (shear_mode + rolling_mode + std::sqrt(gap * gap + 4.0 * cross * cross));
      }
      consider(into, coupled, p.damping_ratio,
               fmt::format("coupled shear and rolling springs of {} (ks = {:.3g} N/m, "
                           "mu_r = {:.3g})",
                           label, p.shear_stiffness, p.rolling_friction));
    }
  };

  for (int a = 0; a < nm; ++a) {
    if (!light[a].present) continue;
    for (int b = a; b < nm; ++b) {
      if (!light[b].present) continue;
      // A lone body of a material never touches its like: its pair only sets the fallback.
      const bool possible = b != a || light[a].bodies >= 2;
      consider_pair(possible ? best : fallback, materials.pair(a, b), a, b,
                    materials[a].name + "-" + materials[b].name +
                        (possible ? " contacts" : " contacts, which cannot occur"));
    }
    for (const auto& w : walls)
      consider_pair(best, materials.pair(a, w.material), a, nm,
                    materials[a].name + " on wall '" + w.name + "'");
  }
  if (!std::isfinite(best.limit) && std::isfinite(fallback.limit)) {
    fallback.contact_possible = false;
    return fallback;
  }
  return best;
}

}  // namespace mfdem::dem
