#include "studies/benchmarks/calibration_functions/direct_search.hpp"

#include <gsl/gsl_rng.h>
#include <nlopt.hpp>

#include <limits>
#include <memory>
#include <stdexcept>

namespace mfdem::benchmarks {
namespace {

nlopt::algorithm algorithm_named(const std::string& name) {
  if (name == "BOBYQA") return nlopt::LN_BOBYQA;
  if (name == "Sbplx") return nlopt::LN_SBPLX;
  if (name == "DIRECT-L") return nlopt::GN_DIRECT_L;
  if (name == "ISRES") return nlopt::GN_ISRES;
  if (name == "CRS2") return nlopt::GN_CRS2_LM;
  throw std::invalid_argument("unknown direct method " + name);
}

struct Search {
  const TestFunction* t;
  const std::function<double(const Eigen::VectorXd&)>* observe;
  int budget;
  double best_observed = std::numeric_limits<double>::infinity();
  double best_gap = 0.0;
  std::vector<TracePoint> trace;
};

struct BudgetSpent {};

double objective(const std::vector<double>& x, std::vector<double>&, void* data) {
  auto* s = static_cast<Search*>(data);
  if (static_cast<int>(s->trace.size()) >= s->budget) throw BudgetSpent{};
  const Eigen::VectorXd p = Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
  const double y = (*s->observe)(p);
  if (y < s->best_observed) s->best_observed = y, s->best_gap = s->t->f(p) - s->t->minimum;
  s->trace.push_back({double(s->trace.size() + 1), s->best_gap});
  return y;
}

}  // namespace

const std::vector<std::string>& direct_methods() {
  static const std::vector<std::string> all = {"BOBYQA", "Sbplx", "DIRECT-L", "ISRES", "CRS2"};
  return all;
}

std::vector<TracePoint> direct_search(const std::string& method, const TestFunction& t,
                                      const std::function<double(const Eigen::VectorXd&)>& observe, int budget,
                                      std::uint64_t seed) {
  const auto d = static_cast<unsigned>(t.bounds.size());
  nlopt::srand(seed);
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(seed * 7919 + 13));
  std::vector<double> lower, upper, x;
  for (const auto& b : t.bounds) {
    lower.push_back(b.lower), upper.push_back(b.upper);
    x.push_back(b.lower + gsl_rng_uniform(rng.get()) * (b.upper - b.lower));
  }
  Search s{&t, &observe, budget};
  // Local methods restart from a new random point when they converge, until the budget is spent:
  // a fair use of the evaluations they are given.
  while (static_cast<int>(s.trace.size()) < budget) {
    nlopt::opt opt(algorithm_named(method), d);
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    opt.set_maxeval(budget);
    opt.set_min_objective(objective, &s);
    if (method == "BOBYQA" || method == "Sbplx") opt.set_xtol_rel(1e-8);
    double value = 0.0;
    const std::size_t before = s.trace.size();
    try {
      opt.optimize(x, value);
    } catch (const BudgetSpent&) {
      break;
    } catch (const std::exception&) {
      // Round-off or a forced stop: restart below.
    }
    if (s.trace.size() == before) break;  // made no progress: nothing more to gain
    for (unsigned a = 0; a < d; ++a) x[a] = lower[a] + gsl_rng_uniform(rng.get()) * (upper[a] - lower[a]);
  }
  return s.trace;
}

}  // namespace mfdem::benchmarks
