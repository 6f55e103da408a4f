#pragma once
// Analytic test functions with known optima for the calibration benchmark (main.cpp): Branin
// (2-D), Hartmann 3-D and the Forrester 1-D pair with its cheap level (Forrester, Sobester &
// Keane 2008; values and minimisers from the Virtual Library of Simulation Experiments, Surjanovic
// & Bingham, sfu.ca/~ssurjano).
#include <Eigen/Dense>

#include <functional>
#include <string>
#include <vector>

#include "calibration/latin_hypercube.hpp"

namespace mfdem::benchmarks {

struct TestFunction {
  std::string name;
  std::vector<calibration::Bounds> bounds;
  std::function<double(const Eigen::VectorXd&)> f;
  std::function<double(const Eigen::VectorXd&)> cheap;  // empty: one level
  double minimum = 0.0;
  std::vector<Eigen::VectorXd> minimisers;
  double range = 0.0;  // max - min over the box (the max from 65,536 Sobol points)
};

std::vector<TestFunction> test_functions();

}  // namespace mfdem::benchmarks
