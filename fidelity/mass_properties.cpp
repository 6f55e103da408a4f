#include "fidelity/mass_properties.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mfdem::fidelity {

Moments& Moments::operator+=(const Moments& other) {
  volume += other.volume;
  first += other.first;
  second += other.second;
  return *this;
}

Moments& Moments::operator-=(const Moments& other) {
  volume -= other.volume;
  first -= other.first;
  second -= other.second;
  return *this;
}

Moments Moments::translated(const Vec3& offset) const {
  // integral of (x + o)(x + o)^T = S + f o^T + o f^T + V o o^T
  Moments moved;
  moved.volume = volume;
  moved.first = first + volume * offset;
  moved.second = second + first * offset.transpose() + offset * first.transpose() + volume * offset * offset.transpose();
  return moved;
}

Moments operator+(Moments a, const Moments& b) { return a += b; }
Moments operator-(Moments a, const Moments& b) { return a -= b; }

Moments ball_moments(const Vec3& centre, double radius) {
  Moments ball;
  ball.volume = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  ball.second = Mat3::Identity() * (ball.volume * radius * radius / 5.0);
  return ball.translated(centre);
}

MassProperties mass_properties(const Moments& moments) {
  if (!(moments.volume > 0.0)) throw std::invalid_argument("mass properties of a solid with no volume");
  MassProperties p;
  p.volume = moments.volume;
  p.centroid = moments.first / moments.volume;
  const Mat3 central = moments.second - p.volume * p.centroid * p.centroid.transpose();
  p.inertia = central.trace() * Mat3::Identity() - central;
  p.inertia = 0.5 * (p.inertia + p.inertia.transpose());
  return p;
}

PrincipalAxes principal_axes(const Mat3& inertia) {
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(inertia);
  PrincipalAxes result;
  result.moments = solver.eigenvalues();
  Mat3 axes = solver.eigenvectors();
  for (int k = 0; k < 2; ++k) {
    Eigen::Index largest = 0;
    axes.col(k).cwiseAbs().maxCoeff(&largest);
    if (axes(largest, k) < 0.0) axes.col(k) = -axes.col(k);
  }
  axes.col(2) = axes.col(0).cross(axes.col(1)).normalized();
  result.axes = axes;
  return result;
}

double relative_tensor_difference(const Mat3& a, const Mat3& b, const Mat3& reference) {
  return (a - b).norm() / reference.norm();
}

}  // namespace mfdem::fidelity
