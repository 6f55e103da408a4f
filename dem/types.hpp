#pragma once
// Basic numeric types shared by the solver.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace mfdem::dem {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Mat3 = Eigen::Matrix3d;
using Index = std::int32_t;

}  // namespace mfdem::dem
