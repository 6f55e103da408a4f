#include "studies/campaigns/paired_statistics.hpp"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mfdem::campaigns {

double mean_of(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / double(values.size());
}

MeanInterval mean_interval(const std::vector<double>& values) {
  MeanInterval m;
  m.n = values.size();
  if (m.n == 0) return m;
  m.mean = mean_of(values);
  if (m.n < 2) {
    m.half_width = std::numeric_limits<double>::infinity();
    return m;
  }
  double squares = 0.0;
  for (double v : values) squares += (v - m.mean) * (v - m.mean);
  m.standard_deviation = std::sqrt(squares / double(m.n - 1));
  m.half_width = gsl_cdf_tdist_Pinv(0.975, double(m.n - 1)) * m.standard_deviation / std::sqrt(double(m.n));
  return m;
}

std::vector<double> relative_differences(const std::vector<double>& model, const std::vector<double>& reference) {
  if (model.size() != reference.size()) throw std::invalid_argument("relative_differences: unpaired lists");
  std::vector<double> d;
  for (std::size_t k = 0; k < model.size(); ++k)
    if (std::isfinite(model[k]) && std::isfinite(reference[k]) && reference[k] != 0.0)
      d.push_back((model[k] - reference[k]) / reference[k]);
  return d;
}

Verdict verdict(const MeanInterval& d, double tolerance) {
  if (d.n == 0) return Verdict::undecided;
  if (d.low() >= -tolerance && d.high() <= tolerance) return Verdict::within;
  if (d.low() > tolerance || d.high() < -tolerance) return Verdict::outside;
  return Verdict::undecided;
}

int seeds_to_decide(const MeanInterval& d, double tolerance, int limit) {
  if (d.n < 2 || !std::isfinite(d.standard_deviation)) return 0;
  const double margin = std::abs(std::abs(d.mean) - tolerance);
  if (!(margin > 0.0)) return 0;
  for (int n = 2; n <= limit; ++n)
    if (gsl_cdf_tdist_Pinv(0.975, double(n - 1)) * d.standard_deviation / std::sqrt(double(n)) < margin) return n;
  return 0;
}

double interpolate_curve(const std::vector<double>& u, const std::vector<double>& f, double at) {
  if (u.empty() || u.size() != f.size()) throw std::invalid_argument("interpolate_curve: empty, or u and F of different lengths");
  const auto above = std::upper_bound(u.begin(), u.end(), at);
  if (above == u.begin()) return f.front();
  if (above == u.end()) return f.back();
  const std::size_t j = static_cast<std::size_t>(above - u.begin()) - 1;
  if (u[j + 1] <= u[j]) return f[j];
  const double w = (at - u[j]) / (u[j + 1] - u[j]);
  return (1.0 - w) * f[j] + w * f[j + 1];
}

double normalised_rms_difference(const std::vector<double>& um, const std::vector<double>& fm,
                                 const std::vector<double>& ur, const std::vector<double>& fr) {
  if (um.size() != fm.size() || ur.size() != fr.size())
    throw std::invalid_argument("normalised_rms_difference: u and F of different lengths");
  if (um.empty() || ur.empty()) return std::numeric_limits<double>::quiet_NaN();
  const double peak = *std::max_element(fr.begin(), fr.end());
  const double u_last = std::min(um.back(), ur.back());
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < ur.size() && ur[k] <= u_last; ++k) {
    const double f = interpolate_curve(um, fm, ur[k]);
    sum += (f - fr[k]) * (f - fr[k]);
    ++n;
  }
  return n > 0 && peak > 0.0 ? std::sqrt(sum / double(n)) / peak : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace mfdem::campaigns
