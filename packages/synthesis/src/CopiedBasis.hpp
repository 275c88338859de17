// The basis of a copy made by "Copies: N", turned from its prototype's
// instead of built again (doc/theory.md §15).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cms/fem/RigidPlacement.hpp"
#include "cms/reduction/RitzBasis.hpp"
#include "cms/substructure/Substructure.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"
#include "PartData.hpp"

namespace cms::synthesis::detail {

using substructure::turnedRows;  // Q X (cms/substructure/Substructure.hpp)

/// V_c = Q V_p, Q turning every node's translations and rotations by `turn`
/// (the copy's placement relative to the prototype's). Exact when the copy
/// is the prototype turned about an axis its loads and supports are
/// symmetric about (K_c = Q K_p Q^T, and so for M, G1, KS1 - KT1): then
/// V_c^T A_c V_c = V_p^T A_p V_p for each. That is checked here, to the
/// rounding of the products (theory §15.2), and the copy's matrices
/// differing from the prototype's turned is reported in `why` with no basis
/// returned (the caller then reduces the copy itself). For a copy whose
/// matrices the assembly turned (A_c = Q A_p Q^T by construction) the caller
/// passes `operatorsTurned`, the outcome of operatorsAreTurned (K and M on
/// a random vector: two products, not eight of the basis' width): true
/// stands for the projections, which run otherwise. Collective.
std::optional<reduction::RitzBasis> turnedBasis(const substructure::Substructure& prototype,
                                                const reduction::RitzBasis& basis,
                                                const substructure::Substructure& copy, const fem::Rotation& turn,
                                                bool operatorsTurned, std::string& why);

/// Whether the copy's K and M are the prototype's turned, Q A_p Q^T = A_c,
/// tested on a random vector to the rounding of the two products
/// (n eps ||A||_F ||x||): then one factorisation of the prototype's serves
/// the copy's solves and inertias (error estimates, coverage). Collective.
bool operatorsAreTurned(const substructure::Substructure& prototype, const substructure::Substructure& copy,
                        const fem::Rotation& turn);

/// The copy's rigid motions as the prototype's mixed (theory §15.2): M6
/// (na x na, column-major) with Y = Xq M6 by least squares through the
/// normal equations (Xq: the prototype's na <= 6 rigid columns, independent;
/// Y: the copy's, turned back), accepted when ||Y - Xq M6||_F <= 1e3 eps
/// ||Y||_F, the rounding of the turn and of the copy's turned coordinates;
/// nullopt when it is not (the copy's attachment moves otherwise than the
/// prototype's turned: the caller projects the copy itself) or when Xq^T Xq
/// is not positive definite. Y is overwritten with the residual.
/// Collective.
std::optional<std::vector<double>> rigidMotionFit(const MultiVector& Xq, MultiVector& Y);

/// The harmonic content of every copied item in one mode: `parts` and `u`
/// (the mode's motion per part, SynthesizedStructure::expand) in tree
/// order. Items whose copies have no DOF table of their own (rigid rotors)
/// or differing tables are left out. Collective.
std::vector<CyclicContent> cyclicContent(const std::vector<std::shared_ptr<AssembledStructure::Part>>& parts,
                                         const std::vector<Teuchos::RCP<MultiVector>>& u);

}  // namespace cms::synthesis::detail
