// vec3.hpp — the small fixed-size vector type of the engine.
// Eigen::Vector3d is 24 bytes with 8-byte alignment, so it is safe in std::vector
// without aligned allocators and packs densely in the contact records.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross()

namespace cdpowder {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

}  // namespace cdpowder
