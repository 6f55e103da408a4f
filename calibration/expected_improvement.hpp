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

// EI x (1 - tau / sqrt(s^2 + tau^2)) with s^2 = variance, tau^2 = noise_variance.
double noise_aware_expected_improvement(double incumbent, double mean, double variance, double noise_variance);

}  // namespace mfdem::calibration
