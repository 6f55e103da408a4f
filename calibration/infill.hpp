#pragma once
// Where to run next: noise-aware expected improvement of the misfit (expected_improvement.hpp)
// over the expensive level's surrogates, its incumbent from expensive runs only, maximised over
// the parameters' box (box_search.hpp). In a two-level study the point is chosen first, then the
// level with the larger improvement per unit cost: EI x the share of the expensive prediction's
// variance a run at that level removes (MisfitSurrogate::variance_share) / its cost (the
// augmented EI of Huang et al. 2006 in its multi-fidelity form; an expensive run comes with its
// cheap twin, which keeps the design nested). A batch of q points for q parallel runs by the
// kriging believer (Ginsbourger, Le Riche & Carraro 2010): each chosen point is added as if run,
// with the outputs the surrogates predict there, and the surrogates are refitted before the next.
#include <span>
#include <vector>

#include "calibration/box_search.hpp"
#include "calibration/misfit_surrogate.hpp"

namespace mfdem::calibration {

struct InfillOptions {
  int batch = 1;            // q: runs proposed at once
  double cheap_cost = 0.25;  // a cheap run's cost, in expensive runs
  BoxSearch search;
};

struct Proposal {
  Eigen::VectorXd parameters;
  Level level = Level::expensive;
  bool with_cheap_twin = false;     // an expensive run of a two-level study: run the cheap level there too
  double expected_improvement = 0.0;  // of the misfit, at the expensive level, when it was chosen
  double cost = 1.0;                  // in expensive runs, twin included
};

// `surrogate` is fitted on `runs`; its settings (bounds, targets, kernel) are reused for the
// believer refits of a batch.
std::vector<Proposal> propose_runs(const MisfitSurrogate& surrogate, std::span<const Evaluation> runs,
                                   const InfillOptions& options);

// The acquisition itself at a point: noise-aware EI of the misfit.
double misfit_expected_improvement(const MisfitSurrogate& surrogate, const Eigen::VectorXd& point);

}  // namespace mfdem::calibration
