// Simulation: the pair force loop, split into thread blocks with a result independent of the thread count.
#include "dem/simulation.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <ranges>

#include "dem/chunked.hpp"

namespace mfdem::dem {

template <bool kPointBodies>
void Simulation::prefill_batch(ContactBatch& batch) const {
  const PairParameters* const pp = one_material_ >= 0 ? &materials_.pair(one_material_, one_material_) : nullptr;
  for (int lane = 0; lane < kContactBatch; ++lane) {
    if (kPointBodies) {
      batch.lax[lane] = batch.lay[lane] = batch.laz[lane] = 0.0;
      batch.lbx[lane] = batch.lby[lane] = batch.lbz[lane] = 0.0;
    }
    if (pp) {
      batch.kn[lane] = pp->normal_stiffness, batch.ks[lane] = pp->shear_stiffness;
      batch.mu[lane] = pp->friction, batch.mu_r[lane] = pp->rolling_friction;
    }
    if (!any_rolling_) batch.mx[lane] = batch.my[lane] = batch.mz[lane] = 0.0;
  }
}

template <bool kPointBodies>
void Simulation::load_lane(ContactBatch& batch, int lane, Index p, const Vec3& d, double d2) const {
  const Index i = pairs_.first[p], j = pairs_.second[p];
  // With only spheres, element k is body k and sits at its centre: no indirection, no lever.
  const Index bi = kPointBodies ? i : elements_.body[i];
  const Index bj = kPointBodies ? j : elements_.body[j];
  batch.dx[lane] = d.x(), batch.dy[lane] = d.y(), batch.dz[lane] = d.z();
  batch.d2[lane] = d2;
  batch.ra[lane] = elements_.radius[i], batch.rb[lane] = elements_.radius[j];
  const Vec3& va = bodies_.velocity[bi];
  const Vec3& vb = bodies_.velocity[bj];
  const Vec3& wa = bodies_.angular_velocity[bi];
  const Vec3& wb = bodies_.angular_velocity[bj];
  batch.vax[lane] = va.x(), batch.vay[lane] = va.y(), batch.vaz[lane] = va.z();
  batch.vbx[lane] = vb.x(), batch.vby[lane] = vb.y(), batch.vbz[lane] = vb.z();
  batch.wax[lane] = wa.x(), batch.way[lane] = wa.y(), batch.waz[lane] = wa.z();
  batch.wbx[lane] = wb.x(), batch.wby[lane] = wb.y(), batch.wbz[lane] = wb.z();
  if constexpr (!kPointBodies) {  // spheres: zero levers, set once by prefill_batch
    const Vec3 la = elements_.position[i] - bodies_.position[bi];
    const Vec3 lb = elements_.position[j] - bodies_.position[bj];
    batch.lax[lane] = la.x(), batch.lay[lane] = la.y(), batch.laz[lane] = la.z();
    batch.lbx[lane] = lb.x(), batch.lby[lane] = lb.y(), batch.lbz[lane] = lb.z();
  }
  if (one_material_ < 0) {  // else set once by prefill_batch
    const PairParameters& pp = materials_.pair(elements_.material[i], elements_.material[j]);
    batch.kn[lane] = pp.normal_stiffness, batch.ks[lane] = pp.shear_stiffness;
    batch.mu[lane] = pp.friction, batch.mu_r[lane] = pp.rolling_friction;
  }
  batch.cn[lane] = pair_dashpot_[p];
  const PairSpring& h = pair_spring_[p];
  batch.sx[lane] = h.shear_force.x(), batch.sy[lane] = h.shear_force.y(), batch.sz[lane] = h.shear_force.z();
  if (any_rolling_) {  // else zero, set once by prefill_batch (and the pair's stays zero)
    const Vec3& m = pair_rolling_[p];
    batch.mx[lane] = m.x(), batch.my[lane] = m.y(), batch.mz[lane] = m.z();
  }
  batch.damping_force[lane] = h.damping_force;
}

void Simulation::store_springs(const ContactBatch& batch, int lane, Index p) {
  PairSpring& h = pair_spring_[p];
  h.shear_force = Vec3(batch.sx[lane], batch.sy[lane], batch.sz[lane]);
  h.damping_force = batch.damping_force[lane];
  if (any_rolling_) pair_rolling_[p] = Vec3(batch.mx[lane], batch.my[lane], batch.mz[lane]);
}

// Pair forces, summed into the elements in increasing pair order whatever the thread count:
// element e takes the pairs where it is second (all earlier in the list than its own row), then
// its own row. Each thread owns a block of bodies, their elements and their rows. A pair whose
// second element lies in a later block is computed first and stored (phase A); then each thread
// adds the stored pairs of earlier blocks to its elements and walks its rows in order (phase B).
// One thread is the one-block case: no stored pairs at all.
void Simulation::evaluate_forces() {
  if (all_point_bodies_)
    evaluate_forces_of<true>();
  else
    evaluate_forces_of<false>();
}

// The first body of thread t's block: the blocks split the neighbour list, the pair loop's work,
// at the shares balance_blocks measured (equal shares at first), rather than the bodies (a bed's
// surface or a sparse region has fewer neighbours per body), and start at a chunk so that
// gather_chunk's chunk sums can follow the same split. The result does not depend on where
// the blocks end.
Index Simulation::pair_block_start(int t) const {
  const Index nb = bodies_.size();
  if (t + 1 >= static_cast<int>(pair_blocks_.share.size())) return nb;
  const auto target = static_cast<Index>(static_cast<double>(pairs_.size()) * pair_blocks_.share[t]);
  // The first body whose rows start at or after the target, to the nearest chunk.
  const Index b = *std::ranges::partition_point(std::views::iota(Index{0}, nb), [&](Index b) {
    return pairs_.row_start[bodies_.element_begin(b)] < target;
  });
  return std::min(nb, chunk_begin((b + kChunkSize / 2) / kChunkSize));
}

int Simulation::team_size() const {
  return bodies_.size() > kChunkSize ? omp_get_max_threads() : 1;
}

// Called by every thread of a team (in a parallel region of team_size() threads, or fewer when
// nested): the blocks planned for this team size. Every thread reads the plan's count before any
// can pass the barrier to the re-plan, so all take the same branch.
const Simulation::PairBlocks& Simulation::team_plan() {
  const int nt = omp_get_num_threads();
  if (pair_blocks_.threads != nt) {
#pragma omp barrier
#pragma omp single
    plan_pair_blocks(nt);
  }
  return pair_blocks_;
}

std::pair<Index, Index> Simulation::thread_bodies() {
  const PairBlocks& plan = team_plan();
  const int t = omp_get_thread_num();
  return {plan.body_start[t], plan.body_start[t + 1]};
}

std::pair<Index, Index> Simulation::thread_chunks() {
  const auto [first, end] = thread_bodies();
  return {first / kChunkSize, chunk_count(end)};  // blocks start at chunks
}

// Moves the block boundaries towards equal measured pair-loop time per thread (as LAMMPS's
// fix balance does by time): a block's share of the neighbour list is scaled by how much faster
// than the average its thread was. Only the split moves, never a result.
void Simulation::balance_blocks() {
  PairBlocks& plan = pair_blocks_;
  const int nt = plan.threads;
  if (nt < 2) return;
  double total = 0.0;
  for (int t = 0; t < nt; ++t) total += plan.busy[t].seconds;
  if (!(total > 0.0)) return;
  std::vector<double> share(nt + 1, 0.0);
  for (int t = 0; t < nt; ++t) {
    const double width = plan.share[t + 1] - plan.share[t];
    const double rate = plan.busy[t].seconds / total * nt;  // 1: the average thread
    // Half way to the share that would have taken the average time, as the costs are noisy.
    share[t + 1] = share[t] + width * (0.5 + 0.5 / std::max(rate, 0.25));
  }
  for (int t = 1; t < nt; ++t) share[t] /= share[nt];
  share[nt] = 1.0;
  for (auto& b : plan.busy) b.seconds = 0.0;
  const std::vector<double> old = plan.share;
  plan.share = share;
  bool moved = false;
  for (int t = 1; t < nt; ++t) moved = moved || pair_block_start(t) != plan.body_start[t];
  if (moved)
    plan.threads = 0;  // re-planned at the next step's drift
  else
    plan.share = old;  // the same blocks: the shares stay those of the blocks measured
}

// Where each thread's block starts, the pairs that cross blocks (phase A of evaluate_forces_of)
// and the ones each block takes from earlier blocks: fixed between two builds.
void Simulation::plan_pair_blocks(int threads) {
  PairBlocks& plan = pair_blocks_;
  if (static_cast<int>(plan.share.size()) != threads + 1) {
    plan.share.resize(threads + 1);
    for (int t = 0; t <= threads; ++t) plan.share[t] = static_cast<double>(t) / threads;
  }
  plan.busy.assign(threads, {});
  plan.threads = threads;
  plan.body_start.resize(threads + 1);
  for (int t = 0; t <= threads; ++t) plan.body_start[t] = pair_block_start(t);
  plan.crossing.clear();
  plan.taken.clear();
  plan.taken_start.assign(1, 0);
  for (int t = 0; t < threads; ++t) {
    const Index e0 = bodies_.element_begin(plan.body_start[t]);
    const Index e1 = bodies_.element_begin(plan.body_start[t + 1]);
    const Index p0 = pairs_.row_start[e0];
    for (Index p = p0; p < pairs_.row_start[e1]; ++p)
      if (pairs_.second[p] >= e1) plan.crossing.push_back(p);
    for (Index e = e0; e < e1; ++e)
      for (Index k = pairs_.as_second_start[e]; k < pairs_.as_second_start[e + 1]; ++k) {
        if (pairs_.as_second_pair[k] >= p0) break;  // as_second lists are in pair order
        plan.taken.push_back(pairs_.as_second_pair[k]);
      }
    plan.taken_start.push_back(static_cast<Index>(plan.taken.size()));
  }
}

template <bool kPointBodies>
void Simulation::evaluate_forces_of() {
  constexpr Index kPairPrefetchDistance = 16;  // work-list entries
  const Index np = pairs_.size();
  const Index ne = elements_.size();
  const int blocks = team_size();
  if (static_cast<int>(pair_work_.size()) < blocks) pair_work_.resize(blocks);
  // The sums start from zero: gather_chunk zeroes them as it reads them, which spares a pass over
  // the elements.
  if (static_cast<Index>(element_force_.size()) != ne) {
    element_force_.assign(ne, Vec3::Zero());
    element_torque_.assign(ne, Vec3::Zero());
    row_damping_.assign(ne, 0.0);
    row_friction_.assign(ne, 0.0);
  }
  pair_damping_.resize(np);
  pair_friction_.resize(np);
  // Spheres only: element k is body k, and the pair sums go straight into the bodies' force and
  // torque (drift_and_kick zeroed them after its half kick), sparing a pass over a second pair
  // of arrays. Clumps sum per element; gather_chunk adds the pebbles' lever torques.
  Vec3* const force_sum = kPointBodies ? bodies_.force.data() : element_force_.data();
  Vec3* const torque_sum = kPointBodies ? bodies_.torque.data() : element_torque_.data();
  const Vec3 length = domain_.length();
  const double dt = dt_;
  prepare_gather();
  Index bad_pair = np;
#pragma omp parallel num_threads(blocks) if (blocks > 1) reduction(min : bad_pair)
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const PairBlocks& plan = team_plan();
    const double start = nt > 1 ? omp_get_wtime() : 0.0;
    double waited = 0.0;  // at the barrier between the phases
    const Index b0 = plan.body_start[t], b1 = plan.body_start[t + 1];
    const Index e0 = bodies_.element_begin(b0), e1 = bodies_.element_begin(b1);
    const Index p0 = pairs_.row_start[e0], p1 = pairs_.row_start[e1];
    // Energy is summed per row (the first element), in pair order, then over elements in
    // chunk order: the same sums on any thread count.
    ContactBatch batch;
    prefill_batch<kPointBodies>(batch);
    Index lane_pair[kContactBatch];
    const double max_overlap = settings_.guards.max_overlap_fraction;
    auto too_deep = [&](int lane) {
      return batch.overlap[lane] > max_overlap * std::min(batch.ra[lane], batch.rb[lane]);
    };
    // Adds pair p to the batch if it touches (and marks it active). An active pair that has
    // opened is left to the caller to release.
    auto load_if_touching = [&](Index p) __attribute__((always_inline)) {
      const Vec3 d = separation(p, length);
      const double d2 = d.squaredNorm();
      if (!overlapping(p, d2)) return false;
      load_lane<kPointBodies>(batch, batch.size, p, d, d2);
      lane_pair[batch.size++] = p;
      pair_active_[p] = 1;  // after the loads: a byte store may alias them all
      return true;
    };
    // Phase A: the pairs whose second element lies in a later block, computed and stored, an
    // equal share of them by each thread. On one thread there are none.
    auto store_batch = [&]() {
      compute_contacts(batch, dt, any_rolling_);
      for (int k = 0; k < batch.size; ++k) {
        const Index p = lane_pair[k];
        store_springs(batch, k, p);
        if (too_deep(k)) bad_pair = std::min(bad_pair, p);
        pair_damping_[p] = batch.dissipated_damping[k];
        pair_friction_[p] = batch.dissipated_friction[k];
        pair_force_[p] = Vec3(batch.fx[k], batch.fy[k], batch.fz[k]);
        pair_torque_first_[p] = Vec3(batch.tax[k], batch.tay[k], batch.taz[k]);
        pair_torque_second_[p] = Vec3(batch.tbx[k], batch.tby[k], batch.tbz[k]);
      }
      batch.size = 0;
    };
    const auto crossing = static_cast<Index>(plan.crossing.size());
    for (Index k = crossing * t / nt; k < crossing * (t + 1) / nt; ++k) {
      const Index p = plan.crossing[k];
      if (batch.size == kContactBatch) store_batch();
      if (load_if_touching(p)) continue;
      pair_damping_[p] = 0.0;
      pair_friction_[p] = pair_active_[p] ? release_pair(p, separation(p, length)) : 0.0;
    }
    if (batch.size > 0) store_batch();
    const double arrived = nt > 1 ? omp_get_wtime() : 0.0;
#pragma omp barrier
    if (nt > 1) waited = omp_get_wtime() - arrived;
    // Phase B: the stored pairs of earlier blocks, each element's in pair order.
    for (Index k = plan.taken_start[t]; k < plan.taken_start[t + 1]; ++k) {
      const Index p = plan.taken[k];
      if (!pair_active_[p]) continue;
      const Index e = pairs_.second[p];
      force_sum[e] += pair_force_[p];
      torque_sum[e] += pair_torque_second_[p];
    }
    // Phase B visits only the pairs that do something: stored ones, touching ones, and active
    // ones that open now. The rest (a third or more of a Verlet list) add nothing, and sorting
    // them out first in a loop without branches spares the pair loop a branch that the CPU
    // mispredicts about every other pair.
    std::vector<Index>& work = pair_work_[t];
    work.resize(p1 - p0);
    Index n_work = 0;
    for (Index p = p0; p < p1; ++p) {
      const bool touching = overlapping(p, separation(p, length).squaredNorm());
      work[n_work] = p;
      n_work += static_cast<Index>((pairs_.second[p] >= e1) | (pair_active_[p] != 0) | touching);
    }
    // Phase B, own rows in pair order: the touching pairs a batch at a time, then their sums
    // (with the stored pairs and the releases between them) in pair order.
    for (Index k0 = 0; k0 < n_work;) {
      Index k1 = k0;
      for (; k1 < n_work; ++k1) {
        const Index p = work[k1];
        if (pairs_.second[p] >= e1) continue;
        if (batch.size == kContactBatch) break;  // this pair starts the next batch
        if (k1 + kPairPrefetchDistance < n_work) {  // see gather_chunk's wall prefetch
          const Index ahead = work[k1 + kPairPrefetchDistance];
          __builtin_prefetch(&pair_spring_[ahead]);
          const Index body = kPointBodies ? pairs_.second[ahead] : elements_.body[pairs_.second[ahead]];
          __builtin_prefetch(&bodies_.velocity[body]);
          __builtin_prefetch(&bodies_.angular_velocity[body]);
        }
        load_if_touching(p);
      }
      if (batch.size > 0) compute_contacts(batch, dt, any_rolling_);
      int lane = 0;
      for (Index k = k0; k < k1; ++k) {
        const Index p = work[k];
        const Index i = pairs_.first[p], j = pairs_.second[p];
        if (j >= e1) {
          row_damping_[i] += pair_damping_[p];
          row_friction_[i] += pair_friction_[p];
          if (!pair_active_[p]) continue;
          force_sum[i] -= pair_force_[p];
          torque_sum[i] += pair_torque_first_[p];
          continue;
        }
        if (lane < batch.size && lane_pair[lane] == p) {
          store_springs(batch, lane, p);
          row_damping_[i] += batch.dissipated_damping[lane];
          row_friction_[i] += batch.dissipated_friction[lane];
          if (too_deep(lane)) bad_pair = std::min(bad_pair, p);
          const Vec3 f(batch.fx[lane], batch.fy[lane], batch.fz[lane]);
          force_sum[i] -= f;
          torque_sum[i] += Vec3(batch.tax[lane], batch.tay[lane], batch.taz[lane]);
          force_sum[j] += f;
          torque_sum[j] += Vec3(batch.tbx[lane], batch.tby[lane], batch.tbz[lane]);
          ++lane;
          continue;
        }
        row_friction_[i] += release_pair(p, separation(p, length));  // an active contact that opened
      }
      batch.size = 0;
      k0 = k1;
    }
    // The thread's bodies now have all their pair forces (no other thread sums into them, and
    // the stored pairs were taken above): it gathers and kicks them without waiting for the
    // others, which never read them again this step.
    for (Index c = b0 / kChunkSize; c < chunk_count(b1); ++c) gather_chunk<kPointBodies>(c);
    if (nt > 1) pair_blocks_.busy[t].seconds += omp_get_wtime() - start - waited;
  }
  for (const auto& acc : pair_chunk_energy_) {
    dissipated_damping_ += acc.damping;
    dissipated_friction_ += acc.friction;
  }
  if (bad_pair < np) {
    const Index i = pairs_.first[bad_pair], j = pairs_.second[bad_pair];
    fail(fmt::format("overlap between bodies {} and {} exceeds {} of the smaller radius "
                     "(stiffness too low for the load, or time step too large)",
                     elements_.body[i], elements_.body[j], settings_.guards.max_overlap_fraction),
         elements_.body[i]);
  }
  finish_gather();
}

}  // namespace mfdem::dem
