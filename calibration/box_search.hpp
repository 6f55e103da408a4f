#pragma once
// The maximum of a cheap function of the parameters over their box (an acquisition, a predicted
// misfit): NLopt's DIRECT-L over the box (global, deterministic), then BOBYQA (local, derivative
// free) from its best point and from any extra starts; the best point found is returned.
#include <Eigen/Dense>

#include <functional>
#include <span>
#include <vector>

#include "calibration/latin_hypercube.hpp"

namespace mfdem::calibration {

struct BoxSearch {
  int global_evaluations = 0;  // 0: 400 per parameter
  int local_evaluations = 200;  // per start
};

struct BoxOptimum {
  Eigen::VectorXd point;
  double value = 0.0;
};

BoxOptimum maximise_over_box(const std::function<double(const Eigen::VectorXd&)>& f, const std::vector<Bounds>& bounds,
                             std::span<const Eigen::VectorXd> extra_starts = {}, const BoxSearch& search = {});

}  // namespace mfdem::calibration
