// A finite-element model moved rigidly: rotated about an axis through a
// pivot, then translated. Used to place a mesh made in its own axes into the
// structure's (a scene's "Placement") and to make the rotated copies of a
// substructure declared with "Copies: N" (doc/theory.md §15).
#pragma once

#include <array>
#include <memory>
#include <string>

#include "cms/fem/FiniteElementModel.hpp"
#include "cms/fem/Vec3.hpp"

namespace cms::fem {

/// A proper rotation x' = R x (row-major 3 x 3).
struct Rotation {
  std::array<std::array<double, 3>, 3> R{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  /// By `radians` about the unit direction of `axis` (right-handed, Rodrigues).
  static Rotation about(const Vec3& axis, double radians);
  Vec3 apply(const Vec3& x) const;
  /// R A R^T of a symmetric 3 x 3 tensor given as its six components
  /// (xx, yy, zz, xy, yz, xz), the order of PointMassSet::inertia.
  std::array<double, 6> applyToTensor(const std::array<double, 6>& a) const;
};

/// The model with every node at pivot + R (x - pivot) + translation, frame
/// section orientations and hinge axes turned by R, point-mass inertia
/// tensors R J R^T.
/// Per-component items (fixed DOFs, springs, dampers) are left as written:
/// they act along the structure's axes, so callers refuse a rotation that
/// does not map them onto themselves (rotationVariantItem; Copies and a
/// scene's Placement both do).
std::shared_ptr<FiniteElementModel> placedModel(const FiniteElementModel& model, const Rotation& rotation,
                                                const Vec3& pivot, const Vec3& translation = {0, 0, 0});

/// The first per-component item of the model (a fixed set, spring or damper,
/// which act along the structure's axes) that the rotation does not map onto
/// itself, as "<kind> '<name>'": a copy turned by R is then not the same
/// structure turned (a spring along x only, turned by 90 degrees about z,
/// would have to act along y). Empty when every item is invariant: diagonal
/// stiffness, damping and fixity tensors D with R D R^T = D to 16 eps |D|.
std::string rotationVariantItem(const FiniteElementModel& model, const Rotation& rotation);

}  // namespace cms::fem
