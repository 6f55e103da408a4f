#pragma once
// The contact law of contact_law.hpp for a batch of element pairs at once: the same equations, in
// the same order (normal, damping, tangential, rolling), written component by component on plain
// arrays, one array element (lane) per pair, so that the compiler evaluates several pairs with
// each SIMD instruction. One pair alone is a long chain of dependent operations (square root,
// division, the Coulomb tests); lanes side by side fill the CPU where a scalar loop waits.
//
// Every lane is computed by the same instructions in the same order, whatever its position in
// the batch and whatever the batch size, and without fused multiply-adds (contact_batch.cpp is
// compiled with -ffp-contract=off): a pair's result does not depend on which pairs share its
// batch, so a thread count that batches pairs differently gives bitwise the same forces.
// compute_contacts is built for several instruction sets (AVX-512, AVX2, baseline x86-64) and
// picks the best at load time; without contraction all give the same bits.
//
// Conventions as contact_law.hpp: the normal points from the first element (a) to the second
// (b); force and moment are those on b; a receives the opposite force and moment plus its own
// lever-arm torque.
#include <cstdint>

namespace mfdem::dem {

inline constexpr int kContactBatch = 16;  // lanes: a multiple of the widest vector (8 doubles)

struct ContactBatch {
  int size = 0;  // lanes in use
  // --- inputs per lane --------------------------------------------------------------------
  // d: separation from a's element centre to b's (periodic image included), m; the pair must
  // touch, |d| < ra + rb.
  alignas(64) double dx[kContactBatch], dy[kContactBatch], dz[kContactBatch];
  // |d|^2 as the caller computed it to decide that the pair touches: the overlap follows from
  // it, so it is > 0 exactly when the caller says so.
  alignas(64) double d2[kContactBatch];
  alignas(64) double ra[kContactBatch], rb[kContactBatch];  // element radii, m
  // Velocities of the bodies' centres (m/s), their angular velocities (rad/s), and the levers
  // from each body's centre to its element's centre (m; zero for a sphere).
  alignas(64) double vax[kContactBatch], vay[kContactBatch], vaz[kContactBatch];
  alignas(64) double vbx[kContactBatch], vby[kContactBatch], vbz[kContactBatch];
  alignas(64) double wax[kContactBatch], way[kContactBatch], waz[kContactBatch];
  alignas(64) double wbx[kContactBatch], wby[kContactBatch], wbz[kContactBatch];
  alignas(64) double lax[kContactBatch], lay[kContactBatch], laz[kContactBatch];
  alignas(64) double lbx[kContactBatch], lby[kContactBatch], lbz[kContactBatch];
  // Pair parameters: kn, ks (N/m), mu, mu_r, and the dashpot cn (N s/m).
  alignas(64) double kn[kContactBatch], ks[kContactBatch], mu[kContactBatch], mu_r[kContactBatch];
  alignas(64) double cn[kContactBatch];
  // --- history, read and updated ----------------------------------------------------------
  alignas(64) double sx[kContactBatch], sy[kContactBatch], sz[kContactBatch];  // tangential spring Fs, N
  alignas(64) double mx[kContactBatch], my[kContactBatch], mz[kContactBatch];  // rolling spring Mr, N m
  alignas(64) double damping_force[kContactBatch];  // kn d - Fn of the last step, N
  // --- outputs ----------------------------------------------------------------------------
  alignas(64) double fx[kContactBatch], fy[kContactBatch], fz[kContactBatch];  // force on b, N
  alignas(64) double tax[kContactBatch], tay[kContactBatch], taz[kContactBatch];  // torque on a, N m
  alignas(64) double tbx[kContactBatch], tby[kContactBatch], tbz[kContactBatch];  // torque on b, N m
  alignas(64) double dissipated_damping[kContactBatch], dissipated_friction[kContactBatch];  // J this step
  alignas(64) double overlap[kContactBatch];  // m
};

// Evaluates the batch's lanes [0, size): forces, torques about each element's centre (the
// caller adds lever x force for a clump's body), energies; updates the springs. `rolling`: false skips the rolling springs (every lane has mu_r = 0).
void compute_contacts(ContactBatch& batch, double dt, bool rolling);

}  // namespace mfdem::dem
