#pragma once
// Stationary anisotropic covariance kernels of a Gaussian process, as functions of the scaled
// distance r = sqrt(sum_i ((x_i - y_i) / l_i)^2) (Rasmussen & Williams 2006, Gaussian Processes
// for Machine Learning, ch. 4, eqs. 4.9 and 4.17):
//   squared exponential  k = s2 exp(-r^2 / 2)
//   Matern 5/2           k = s2 (1 + sqrt(5) r + 5 r^2 / 3) exp(-sqrt(5) r)
// s2 the signal variance. Matern 5/2 is the default: twice differentiable, not infinitely smooth,
// which suits a response measured through a noisy simulation (Forrester, Sobester & Keane 2008).
#include <Eigen/Dense>

namespace mfdem::calibration {

enum class KernelKind { matern52, squared_exponential };

// k / s2 at scaled distance r >= 0.
double kernel_correlation(KernelKind kind, double r);

// d(k / s2) / d(log l_i) = kernel_log_scale_factor(kind, r) x ((x_i - y_i) / l_i)^2: the same
// factor for every axis (SE: exp(-r^2 / 2); Matern 5/2: 5/3 (1 + sqrt(5) r) exp(-sqrt(5) r)).
double kernel_log_scale_factor(KernelKind kind, double r);

// Scaled distance of x and y with length scales l (all of one size).
double scaled_distance(const Eigen::VectorXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& length_scales);

}  // namespace mfdem::calibration
