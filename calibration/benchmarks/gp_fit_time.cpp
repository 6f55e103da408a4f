// Benchmark (not a test): the wall time of a Gaussian-process fit (the hyperparameter search
// included) against the number of points and of inputs, so that a user knows where the cost
// starts to matter. Medians of 3 fits of a smooth test function on Sobol points.
//   build/calibration/mfdem_gp_fit_benchmark [largest n, default 500]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "calibration/gaussian_process.hpp"
#include "calibration/sobol_design.hpp"

int main(int argc, char** argv) {
  using namespace mfdem::calibration;
  const int largest = argc > 1 ? std::atoi(argv[1]) : 500;
  fmt::print("Gaussian-process fit time (Matern 5/2, default search: DIRECT-L 300 evaluations, then 9 L-BFGS "
             "starts of up to 200), median of 3, s\n");
  fmt::print("{:>6}", "n");
  for (int d = 1; d <= 4; ++d) fmt::print(" {:>10}", fmt::format("d = {}", d));
  fmt::print("\n");
  for (int n : {10, 20, 50, 100, 200, 500}) {
    if (n > largest) break;
    fmt::print("{:>6}", n);
    for (int d = 1; d <= 4; ++d) {
      const std::vector<Bounds> box(d, Bounds{0.0, 1.0});
      const auto design = sobol_design(box, n, 1);
      Eigen::MatrixXd x(n, d);
      Eigen::VectorXd y(n);
      for (int i = 0; i < n; ++i) {
        for (int a = 0; a < d; ++a) x(i, a) = design[i][a];
        y(i) = std::sin(3.0 * x(i, 0)) + (d > 1 ? x(i, 1) * x(i, 1) : 0.0) + 0.01 * std::cos(17.0 * i);
      }
      std::vector<double> times;
      for (int r = 0; r < 3; ++r) {
        GaussianProcess gp(box);
        const auto start = std::chrono::steady_clock::now();
        gp.fit(x, y);
        times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      std::sort(times.begin(), times.end());
      fmt::print(" {:>10.3g}", times[1]);
      std::fflush(stdout);
    }
    fmt::print("\n");
  }
}
