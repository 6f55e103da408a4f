#include "dem/contact_batch.hpp"

#include <algorithm>
#include <cmath>

// Built with -ffp-contract=off (dem/CMakeLists.txt): see contact_batch.hpp.
namespace mfdem::dem {
namespace {

// rotate_to_frame of contact_law.hpp for one lane: the spring (x, y, z) loses its component
// along the new normal n, turns about n by `turn` (rad), and keeps its length. Both branches
// are computed and one is kept, so that lanes need no jumps.
[[gnu::always_inline]] inline void rotate_lane(double& x, double& y, double& z, double nx, double ny, double nz,
                                               double turn) {
  const double m2 = x * x + y * y + z * z;
  const double along = x * nx + y * ny + z * nz;
  double tx = x - along * nx, ty = y - along * ny, tz = z - along * nz;
  const double cx = ny * tz - nz * ty, cy = nz * tx - nx * tz, cz = nx * ty - ny * tx;
  tx += turn * cx;
  ty += turn * cy;
  tz += turn * cz;
  const double across2 = m2 - along * along;
  const double t2 = across2 > 0.5 * m2 ? across2 * (1.0 + turn * turn) : tx * tx + ty * ty + tz * tz;
  const double scale = std::sqrt(m2 / t2);
  const bool keep = m2 > 0.0 && t2 > 0.0;  // else the spring is zero, or lies along n: zero
  x = keep ? tx * scale : 0.0;
  y = keep ? ty * scale : 0.0;
  z = keep ? tz * scale : 0.0;
}

// spring_with_slip of contact_law.hpp for one lane: increment by -k dt rate, cap at `limit`;
// returns the energy the slip dissipated (trapezoid rule), J.
[[gnu::always_inline]] inline double slip_lane(double& x, double& y, double& z, double rx, double ry, double rz,
                                               double stiffness, double dt, double limit) {
  const double px = x, py = y, pz = z;
  const double k_dt = stiffness * dt;
  x -= k_dt * rx;
  y -= k_dt * ry;
  z -= k_dt * rz;
  const double m2 = x * x + y * y + z * z;
  const double m = std::sqrt(m2);
  const bool slipping = m2 > limit * limit && m > limit;
  const double slip = (m - limit) / stiffness;
  const double previous_along_slip = (px * x + py * y + pz * z) / m;
  const double scale = limit / m;
  const double energy = 0.5 * (limit + previous_along_slip) * slip;
  x = slipping ? x * scale : x;
  y = slipping ? y * scale : y;
  z = slipping ? z * scale : z;
  return slipping ? energy : 0.0;
}

template <bool kRolling>
[[gnu::always_inline]] inline void compute_lanes(ContactBatch& b, double dt) {
  const int n = b.size;
#pragma omp simd
  for (int k = 0; k < n; ++k) {
    // Geometry: unit normal a -> b, overlap, arms from the element centres to the contact point
    // (the middle of the overlap), levers from the bodies' centres.
    const double r = std::sqrt(b.d2[k]);
    const double inverse = 1.0 / r;
    const double nx = b.dx[k] * inverse, ny = b.dy[k] * inverse, nz = b.dz[k] * inverse;
    const double reach = b.ra[k] + b.rb[k];
    const double overlap = reach - r;
    const double arm_a = b.ra[k] - 0.5 * overlap, arm_b = b.rb[k] - 0.5 * overlap;
    const double cax = b.lax[k] + arm_a * nx, cay = b.lay[k] + arm_a * ny, caz = b.laz[k] + arm_a * nz;
    const double cbx = b.lbx[k] - arm_b * nx, cby = b.lby[k] - arm_b * ny, cbz = b.lbz[k] - arm_b * nz;
    // Relative velocity of b's surface to a's at the contact point: v + w x c of each.
    const double rvx = (b.vbx[k] + (b.wby[k] * cbz - b.wbz[k] * cby)) - (b.vax[k] + (b.way[k] * caz - b.waz[k] * cay));
    const double rvy = (b.vby[k] + (b.wbz[k] * cbx - b.wbx[k] * cbz)) - (b.vay[k] + (b.waz[k] * cax - b.wax[k] * caz));
    const double rvz = (b.vbz[k] + (b.wbx[k] * cby - b.wby[k] * cbx)) - (b.vaz[k] + (b.wax[k] * cay - b.way[k] * cax));
    const double turn =
        0.5 * ((b.wax[k] + b.wbx[k]) * nx + (b.way[k] + b.wby[k]) * ny + (b.waz[k] + b.wbz[k]) * nz) * dt;

    // 1. Normal: spring and dashpot, never tensile; the dashpot's work over the step.
    const double vn = rvx * nx + rvy * ny + rvz * nz;
    const double elastic = b.kn[k] * overlap;
    const double fn = std::max(0.0, elastic - b.cn[k] * vn);
    b.dissipated_damping[k] = 0.5 * ((elastic - fn) + b.damping_force[k]) * vn * dt;
    b.damping_force[k] = elastic - fn;

    // 2. Tangential: the spring turns with the contact frame, grows, slips at mu Fn.
    const double vtx = rvx - vn * nx, vty = rvy - vn * ny, vtz = rvz - vn * nz;
    double sx = b.sx[k], sy = b.sy[k], sz = b.sz[k];
    rotate_lane(sx, sy, sz, nx, ny, nz, turn);
    double friction = slip_lane(sx, sy, sz, vtx, vty, vtz, b.ks[k], dt, b.mu[k] * fn);
    b.sx[k] = sx, b.sy[k] = sy, b.sz[k] = sz;
    const double fx = fn * nx + sx, fy = fn * ny + sy, fz = fn * nz + sz;
    b.fx[k] = fx, b.fy[k] = fy, b.fz[k] = fz;

    // Torques about the element centres: arm x force on b (arm -arm_b n), minus on a (+arm_a n).
    double tax = -(arm_a * (ny * fz - nz * fy)), tay = -(arm_a * (nz * fx - nx * fz)), taz = -(arm_a * (nx * fy - ny * fx));
    double tbx = -arm_b * (ny * fz - nz * fy), tby = -arm_b * (nz * fx - nx * fz), tbz = -arm_b * (nx * fy - ny * fx);

    // 3. Rolling: the spring on the relative rolling spin, capped at mu_r Rbar Fn.
    if constexpr (kRolling) {
      const double rbar = b.ra[k] * b.rb[k] / reach;
      const double wsx = b.wbx[k] - b.wax[k], wsy = b.wby[k] - b.way[k], wsz = b.wbz[k] - b.waz[k];
      const double spin_n = wsx * nx + wsy * ny + wsz * nz;
      double mx = b.mx[k], my = b.my[k], mz = b.mz[k];
      rotate_lane(mx, my, mz, nx, ny, nz, turn);
      friction += slip_lane(mx, my, mz, wsx - spin_n * nx, wsy - spin_n * ny, wsz - spin_n * nz,
                            b.ks[k] * rbar * rbar, dt, b.mu_r[k] * rbar * fn);
      b.mx[k] = mx, b.my[k] = my, b.mz[k] = mz;
      tax -= mx, tay -= my, taz -= mz;
      tbx += mx, tby += my, tbz += mz;
    }
    b.tax[k] = tax, b.tay[k] = tay, b.taz[k] = taz;
    b.tbx[k] = tbx, b.tby[k] = tby, b.tbz[k] = tbz;
    b.dissipated_friction[k] = friction;
    b.overlap[k] = overlap;
  }
}

}  // namespace

// Cloned per instruction set; the lane loops are inlined into each clone.
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
void compute_contacts(ContactBatch& batch, double dt, bool rolling) {
  if (rolling)
    compute_lanes<true>(batch, dt);
  else
    compute_lanes<false>(batch, dt);
}

}  // namespace mfdem::dem
