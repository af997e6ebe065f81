// ts codec — rigid motion of a frame: the 6 parameters the paper codes with LPC.
// Shared by encoder and decoder (no PCL here: the estimation lives in align.cpp).
//
// Convention: a frame's points v map onto the reference frame as p = R v + T, where R is the
// rotation whose rotation vector (axis * angle, radians) is rot[0..2] and T = trans[0..2]
// (the take's units). The decoder inverts it as v = R^T (p - T).
#pragma once

#include <Eigen/Core>

namespace capz {
namespace ts {

struct RigidParams {
  double rot[3] = {0, 0, 0};    // rotation vector, radians
  double trans[3] = {0, 0, 0};  // translation, the take's units
};

// Rodrigues' formula; deterministic (the decoder calls the same code on the same doubles).
Eigen::Matrix3d rotation_matrix(const RigidParams& p);
// Rotation vector of a rotation matrix (angle in [0, pi]); `m` must be orthonormal.
RigidParams params_from_transform(const Eigen::Matrix3d& rot, const Eigen::Vector3d& trans);

// Applies p = R v + T to `points` 3-vectors in place (xyz interleaved).
void apply_rigid(const RigidParams& p, double* xyz, size_t points);
// Applies v = R^T (p - T) to `points` 3-vectors in place.
void apply_rigid_inverse(const RigidParams& p, double* xyz, size_t points);

}  // namespace ts
}  // namespace capz
