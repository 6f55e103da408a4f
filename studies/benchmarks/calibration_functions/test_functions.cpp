#include "studies/benchmarks/calibration_functions/test_functions.hpp"

#include <cmath>
#include <numbers>

#include "calibration/sobol_design.hpp"

namespace mfdem::benchmarks {
namespace {

double branin(const Eigen::VectorXd& x) {
  const double pi = std::numbers::pi;
  const double b = 5.1 / (4 * pi * pi), c = 5 / pi, t = 1 / (8 * pi);
  return std::pow(x(1) - b * x(0) * x(0) + c * x(0) - 6, 2) + 10 * (1 - t) * std::cos(x(0)) + 10;
}

double hartmann3(const Eigen::VectorXd& x) {
  static const double alpha[4] = {1.0, 1.2, 3.0, 3.2};
  static const double a[4][3] = {{3.0, 10, 30}, {0.1, 10, 35}, {3.0, 10, 30}, {0.1, 10, 35}};
  static const double p[4][3] = {{0.3689, 0.1170, 0.2673}, {0.4699, 0.4387, 0.7470}, {0.1091, 0.8732, 0.5547},
                                 {0.03815, 0.5743, 0.8828}};
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    double inner = 0.0;
    for (int j = 0; j < 3; ++j) inner += a[i][j] * std::pow(x(j) - p[i][j], 2);
    sum += alpha[i] * std::exp(-inner);
  }
  return -sum;
}

double forrester(const Eigen::VectorXd& x) { return std::pow(6 * x(0) - 2, 2) * std::sin(12 * x(0) - 4); }
double forrester_cheap(const Eigen::VectorXd& x) { return 0.5 * forrester(x) + 10 * (x(0) - 0.5) - 5; }

Eigen::VectorXd point(std::initializer_list<double> v) {
  Eigen::VectorXd p(static_cast<Eigen::Index>(v.size()));
  Eigen::Index k = 0;
  for (double x : v) p(k++) = x;
  return p;
}

void set_range(TestFunction& t) {
  double highest = -1e300;
  for (const auto& x : calibration::sobol_design(t.bounds, 65536))
    highest = std::max(highest, t.f(Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()))));
  t.range = highest - t.minimum;
}

}  // namespace

std::vector<TestFunction> test_functions() {
  const double pi = std::numbers::pi;
  std::vector<TestFunction> all = {
      {"branin", {{-5.0, 10.0}, {0.0, 15.0}}, branin, {}, 0.397887357729739,
       {point({-pi, 12.275}), point({pi, 2.275}), point({9.42477796, 2.475})}},
      {"hartmann3", {{0.0, 1.0}, {0.0, 1.0}, {0.0, 1.0}}, hartmann3, {}, -3.86278214782076,
       {point({0.114614, 0.555649, 0.852547})}},
      {"forrester", {{0.0, 1.0}}, forrester, forrester_cheap, -6.02074005576708, {point({0.757248757841856})}},
  };
  for (auto& t : all) set_range(t);
  return all;
}

}  // namespace mfdem::benchmarks
