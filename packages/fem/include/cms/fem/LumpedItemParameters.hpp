// The lumped items of a finite-element model read from their ParameterList
// sublists ("Point Masses", "Springs", "Dampers", "Hinges", "Structural
// Damping", "Boundary Conditions"; doc/user-guide.md): shared by a "Finite
// Element Model" and a scene's built-in "Beam".
#pragma once

#include <string>

#include <Teuchos_ParameterList.hpp>

#include "cms/fem/FiniteElementModel.hpp"

namespace cms::fem {

/// The keys above that `params` has, each checked, appended to `m` (its node
/// sets are checked later, against the mesh, by FiniteElementModel::validate).
/// Throws cms::InputError naming `path` and the key.
void readLumpedItems(const Teuchos::ParameterList& params, const std::string& path, FiniteElementModel& m);

/// The valid sublists, for a caller's key checks.
Teuchos::ParameterList lumpedItemKeys();

}  // namespace cms::fem
