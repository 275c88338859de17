// Admissible vectors (seed, "System discretization"): static deflection shapes
// of the substructure with its held DOFs fixed, under load patterns, continued
// by load-dependent Ritz vectors x_{k+1} = K^-1 M x_k (Wilson, Yuan & Dickens
// 1982). They satisfy the geometric boundary conditions at the attachment and
// need no eigenproblem (doc/theory.md §11.3).
#pragma once

#include <string>
#include <vector>

#include "cms/reduction/RitzBasis.hpp"

namespace cms::reduction {

/// `patterns`: "interfaces", "uniform", "centrifugal", "tip" (see
/// validParameters()). Returns up to `count` M-orthonormal columns in the
/// order static shapes (pattern by pattern), then Krylov blocks; fewer only
/// when the Krylov sequence stops growing (reported in `dropped`).
RitzBasis admissibleVectors(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                            const std::vector<std::string>& patterns, int count, double dependenceTolerance);

}  // namespace cms::reduction
