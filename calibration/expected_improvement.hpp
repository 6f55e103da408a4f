#pragma once
// Expected improvement of a quantity to be minimised (Jones, Schonlau & Welch 1998, J. Global
// Optimization 13:455-492): for Y ~ N(m, s^2) and the incumbent I,
//   EI = E[max(I - Y, 0)] = (I - m) Phi(z) + s phi(z),  z = (I - m) / s,   (max(I - m, 0) at s = 0).
// Noise-aware (Huang, Allen, Notz & Zeng 2006, J. Global Optimization 34:441-466, "augmented
// EI"): the incumbent is the best posterior mean at the points already run (not the best noisy
// observation: one lucky seed would end the search), and EI is scaled by 1 - tau / sqrt(s^2 +
// tau^2), tau^2 the observation noise, so that a point whose uncertainty is all noise is not run
// again and again.
namespace mfdem::calibration {

double expected_improvement(double incumbent, double mean, double standard_deviation);

// The exact EI of a squared scaled error M = ((Y - t) / scale)^2, Y ~ N(m, s^2): the integral
// of I - M over |Y - t| < scale sqrt(I), in closed form with the normal's partial moments. A
// one-output misfit is such a square; its normal approximation misjudges it near the target,
// where M piles up at 0.
double squared_error_expected_improvement(double incumbent, double mean, double standard_deviation, double target,
                                          double scale);

// Huang's factor 1 - tau / sqrt(s^2 + tau^2), s^2 = variance, tau^2 = noise_variance (1 without noise).
double noise_factor(double variance, double noise_variance);

// EI x noise_factor.
double noise_aware_expected_improvement(double incumbent, double mean, double variance, double noise_variance);

}  // namespace mfdem::calibration
