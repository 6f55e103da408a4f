#pragma once
// Mass properties of a rigid solid of unit density.
//
// Moments are the integrals of 1, x and x x^T over the solid about the origin of the frame they
// are written in. They add over disjoint parts, which is how a triangle mesh (one tetrahedron per
// triangle) and a union of spheres (sum of balls minus the overlap excess) are assembled. From
// them follow the volume, the centroid and the inertia tensor about the centroid,
//   I = integral of (|r|^2 1 - r r^T) dV,  r = x - centroid,
// per unit density: multiply by the density in kg/m^3 to get kg m^2 (for lengths in metres).
#include "dem/types.hpp"

namespace mfdem::fidelity {

using dem::Mat3;
using dem::Quat;
using dem::Vec3;

struct Moments {
  double volume = 0.0;         // integral of 1
  Vec3 first = Vec3::Zero();   // integral of x
  Mat3 second = Mat3::Zero();  // integral of x x^T

  Moments& operator+=(const Moments& other);
  Moments& operator-=(const Moments& other);
  // The same solid written in a frame whose origin sits at -offset (every point moved by +offset).
  Moments translated(const Vec3& offset) const;
};

Moments operator+(Moments a, const Moments& b);
Moments operator-(Moments a, const Moments& b);

// A ball of the given centre and radius: volume 4/3 pi R^3, integral of x x^T about its centre
// V R^2 / 5 times the identity.
Moments ball_moments(const Vec3& centre, double radius);

struct MassProperties {
  double volume = 0.0;
  Vec3 centroid = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();  // about the centroid, per unit density
};

// Requires moments.volume > 0.
MassProperties mass_properties(const Moments& moments);

// Principal axes of an inertia tensor: moments ascending (the first axis is the long axis of an
// elongated body) and the axes as the columns of a proper rotation (determinant +1). Signs are
// fixed so that the same tensor always gives the same frame: the largest component of the first
// two axes is positive and the third is their cross product.
struct PrincipalAxes {
  Vec3 moments = Vec3::Zero();
  Mat3 axes = Mat3::Identity();  // column k = axis k in the frame the tensor was written in
};

PrincipalAxes principal_axes(const Mat3& inertia);

// || a - b ||_F / || reference ||_F: the relative difference of two inertia tensors written in the
// same frame.
double relative_tensor_difference(const Mat3& a, const Mat3& b, const Mat3& reference);

}  // namespace mfdem::fidelity
