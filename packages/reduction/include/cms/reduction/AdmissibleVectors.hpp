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

/// `patterns`: "interfaces", "uniform", "rotation", "centrifugal", "tip"
/// (see validParameters()). Returns up to `count` M-orthonormal columns: the
/// interface shapes first, then, one at a time, the softest (lowest Rayleigh
/// quotient after projection) of the other static shapes and the Krylov
/// continuations K^-1 M x of the columns kept; fewer only when no candidate
/// is left (reported in `dropped`).
RitzBasis admissibleVectors(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                            const std::vector<std::string>& patterns, int count, double dependenceTolerance);

/// Polynomial admissible functions evaluated at the nodes (beam-like
/// substructures; doc/theory.md §11.3): along the axis from the held nodes'
/// centroid to the farthest node, s = distance along it / its length; for
/// degree k = 1, 2, ...: bending s^(k+1) in the two transverse directions
/// (frame rotations their slopes), axial s^k, torsion s^k (a rotation about
/// the axis). They vanish at the attachment (s = 0) to first order, and the
/// held rows are zeroed exactly. Needs held DOFs (an attachment).
RitzBasis polynomialVectors(const substructure::Substructure& s, const SubstructureBoundary& boundary, int count,
                            double dependenceTolerance);

}  // namespace cms::reduction
