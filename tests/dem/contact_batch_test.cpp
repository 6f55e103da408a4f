// The batched pair kernel (dem/contact_batch.hpp) against the reference form of the contact law
// (dem/contact_law.hpp, evaluate_contact), on random contacts that stick, slip, roll, turn and
// sit on clump pebbles off their bodies' centres.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "dem/contact_batch.hpp"
#include "dem/contact_law.hpp"

namespace {

using mfdem::dem::ContactBatch;
using mfdem::dem::ContactGeometry;
using mfdem::dem::ContactHistory;
using mfdem::dem::PairParameters;
using mfdem::dem::Vec3;

struct RandomContact {
  Vec3 d, va, vb, wa, wb, la, lb;  // separation a -> b, velocities, spins, levers
  double ra = 0.0, rb = 0.0, cn = 0.0;
  PairParameters p;
  ContactHistory h;
};

RandomContact random_contact(std::mt19937_64& rng, bool rolling) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.0, 1.0);
  auto vec = [&](double scale) -> Vec3 { return Vec3(u(rng), u(rng), u(rng)) * scale; };
  RandomContact c;
  c.ra = 0.01 + 0.02 * pos(rng);
  c.rb = 0.01 + 0.02 * pos(rng);
  const double overlap = 0.05 * std::min(c.ra, c.rb) * pos(rng);
  c.d = vec(1.0).normalized() * (c.ra + c.rb - overlap);
  c.va = vec(0.5), c.vb = vec(0.5), c.wa = vec(20.0), c.wb = vec(20.0);
  c.la = pos(rng) < 0.5 ? Vec3(Vec3::Zero()) : vec(0.02);
  c.lb = pos(rng) < 0.5 ? Vec3(Vec3::Zero()) : vec(0.02);
  c.p.normal_stiffness = 1e6 * std::pow(1e3, pos(rng));  // stiffness ratios up to 1e3
  c.p.shear_stiffness = c.p.normal_stiffness * (0.2 + pos(rng));
  c.p.friction = pos(rng) < 0.1 ? 0.0 : 10.0 * pos(rng) * pos(rng);
  c.p.rolling_friction = rolling && pos(rng) < 0.8 ? pos(rng) : 0.0;
  c.cn = 50.0 * pos(rng);
  // Springs loaded up to about twice their Coulomb limit, not in the contact plane: every branch
  // (stick, slip, the turn of the frame) is taken.
  const double fn = c.p.normal_stiffness * overlap;
  c.h.shear_force = vec(2.0 * c.p.friction * fn);
  c.h.rolling_moment = c.p.rolling_friction > 0.0 ? vec(2.0 * c.p.rolling_friction * 0.01 * fn) : Vec3(Vec3::Zero());
  c.h.damping_force = fn * u(rng);
  return c;
}

// The reference: geometry as the pair loop sets it up, then evaluate_contact.
struct Reference {
  mfdem::dem::ContactOutcome out;
  ContactHistory h;
  Vec3 torque_a, torque_b;
};

Reference reference(const RandomContact& c, double dt) {
  Reference r;
  r.h = c.h;
  const double dist = c.d.norm();
  ContactGeometry g;
  g.normal = c.d / dist;
  g.overlap = c.ra + c.rb - dist;
  const Vec3 arm_a = (c.ra - 0.5 * g.overlap) * g.normal;
  const Vec3 arm_b = -(c.rb - 0.5 * g.overlap) * g.normal;
  g.relative_velocity = (c.vb + c.wb.cross(c.lb + arm_b)) - (c.va + c.wa.cross(c.la + arm_a));
  g.relative_spin = c.wb - c.wa;
  g.frame_spin = 0.5 * (c.wa + c.wb).dot(g.normal);
  g.damping = c.cn;
  g.rolling_radius = c.ra * c.rb / (c.ra + c.rb);
  r.out = mfdem::dem::evaluate_contact(c.p, g, r.h, dt);
  r.torque_a = -arm_a.cross(r.out.force) - r.out.rolling_moment;
  r.torque_b = arm_b.cross(r.out.force) + r.out.rolling_moment;
  return r;
}

void load(ContactBatch& b, int k, const RandomContact& c) {
  b.dx[k] = c.d.x(), b.dy[k] = c.d.y(), b.dz[k] = c.d.z(), b.d2[k] = c.d.squaredNorm();
  b.ra[k] = c.ra, b.rb[k] = c.rb;
  b.vax[k] = c.va.x(), b.vay[k] = c.va.y(), b.vaz[k] = c.va.z();
  b.vbx[k] = c.vb.x(), b.vby[k] = c.vb.y(), b.vbz[k] = c.vb.z();
  b.wax[k] = c.wa.x(), b.way[k] = c.wa.y(), b.waz[k] = c.wa.z();
  b.wbx[k] = c.wb.x(), b.wby[k] = c.wb.y(), b.wbz[k] = c.wb.z();
  b.lax[k] = c.la.x(), b.lay[k] = c.la.y(), b.laz[k] = c.la.z();
  b.lbx[k] = c.lb.x(), b.lby[k] = c.lb.y(), b.lbz[k] = c.lb.z();
  b.kn[k] = c.p.normal_stiffness, b.ks[k] = c.p.shear_stiffness, b.mu[k] = c.p.friction;
  b.mu_r[k] = c.p.rolling_friction, b.cn[k] = c.cn;
  b.sx[k] = c.h.shear_force.x(), b.sy[k] = c.h.shear_force.y(), b.sz[k] = c.h.shear_force.z();
  b.mx[k] = c.h.rolling_moment.x(), b.my[k] = c.h.rolling_moment.y(), b.mz[k] = c.h.rolling_moment.z();
  b.damping_force[k] = c.h.damping_force;
}

// The two forms differ only in the order of a few sums (Eigen's against the lanes'): a few ulps
// of each term, against the largest force, moment or energy in play.
bool close(const Vec3& a, const Vec3& b, double scale) { return (a - b).norm() <= 1e-12 * scale; }
bool close(double a, double b, double scale) { return std::abs(a - b) <= 1e-12 * scale; }

}  // namespace

TEST_CASE("the batched pair kernel gives the contact law's forces, torques, springs and energies",
          "[dem][contact]") {
  const double dt = 1e-5;
  std::mt19937_64 rng(20261202);
  for (bool rolling : {false, true}) {
    CAPTURE(rolling);
    for (int round = 0; round < 40; ++round) {
      ContactBatch batch;
      RandomContact c[mfdem::dem::kContactBatch];
      batch.size = 1 + round % mfdem::dem::kContactBatch;
      for (int k = 0; k < batch.size; ++k) load(batch, k, c[k] = random_contact(rng, rolling));
      mfdem::dem::compute_contacts(batch, dt, rolling);
      for (int k = 0; k < batch.size; ++k) {
        const Reference r = reference(c[k], dt);
        const double force_scale = r.out.force.norm() + r.h.shear_force.norm() + c[k].h.shear_force.norm() + 1e-300;
        const double moment_scale = force_scale * 0.1 + r.h.rolling_moment.norm() + c[k].h.rolling_moment.norm();
        const double energy_scale = std::abs(r.out.dissipated_damping) + std::abs(r.out.dissipated_friction) +
                                    force_scale * (c[k].vb - c[k].va).norm() * dt + 1e-300;
        CAPTURE(round, k, r.out.force, r.out.dissipated_friction);
        CHECK(close(Vec3(batch.fx[k], batch.fy[k], batch.fz[k]), r.out.force, force_scale));
        CHECK(close(Vec3(batch.sx[k], batch.sy[k], batch.sz[k]), r.h.shear_force, force_scale));
        CHECK(close(batch.damping_force[k], r.h.damping_force, force_scale + std::abs(c[k].h.damping_force)));
        CHECK(close(Vec3(batch.mx[k], batch.my[k], batch.mz[k]), r.h.rolling_moment, moment_scale));
        CHECK(close(Vec3(batch.tax[k], batch.tay[k], batch.taz[k]), r.torque_a, moment_scale));
        CHECK(close(Vec3(batch.tbx[k], batch.tby[k], batch.tbz[k]), r.torque_b, moment_scale));
        CHECK(close(batch.dissipated_damping[k], r.out.dissipated_damping, energy_scale));
        CHECK(close(batch.dissipated_friction[k], r.out.dissipated_friction, energy_scale));
      }
    }
  }
}

TEST_CASE("a pair's result in the batched kernel does not depend on its lane or its batch", "[dem][contact][threads]") {
  // Threads batch the pairs differently; each pair must still get the same bits.
  const double dt = 1e-5;
  std::mt19937_64 rng(7);
  ContactBatch full;
  full.size = mfdem::dem::kContactBatch;
  RandomContact c[mfdem::dem::kContactBatch];
  for (int k = 0; k < full.size; ++k) load(full, k, c[k] = random_contact(rng, true));
  mfdem::dem::compute_contacts(full, dt, true);
  for (int k = 0; k < full.size; ++k) {
    ContactBatch alone;
    alone.size = 1;
    load(alone, 0, c[k]);
    mfdem::dem::compute_contacts(alone, dt, true);
    const double a[] = {alone.fx[0], alone.fy[0], alone.fz[0], alone.tax[0], alone.tbz[0], alone.sx[0], alone.mz[0],
                        alone.dissipated_damping[0], alone.dissipated_friction[0]};
    const double b[] = {full.fx[k], full.fy[k], full.fz[k], full.tax[k], full.tbz[k], full.sx[k], full.mz[k],
                        full.dissipated_damping[k], full.dissipated_friction[k]};
    CAPTURE(k);
    CHECK(std::memcmp(a, b, sizeof a) == 0);
  }
}
