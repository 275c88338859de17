// Exact substructure modes: the lowest eigenvectors of K phi = omega^2 M phi
// at rest with the given DOFs held (the attachment to the parent, and for
// Craig-Bampton the children's interfaces too), by Anasazi's Block
// Krylov-Schur on the shift-invert operator K_held^-1 M_held in the M inner
// product (block size 2, so double eigenvalues of symmetric rotors are both
// found), or by LAPACK when the substructure is small (doc/theory.md §11.3).
// A repeated eigenvalue is never split: when the last mode asked for has
// copies (to 1e-8), they are all kept, and the report says so.
#pragma once

#include <vector>

#include "cms/reduction/RitzBasis.hpp"

namespace cms::reduction {

/// Linear constraints H u = 0 on the modes besides the held rows, given by
/// F = H^T (n x m: the loads of the constrained coordinates) and
/// Y = K_held^-1 F (the static shapes under them): the modes are then those
/// of K phi = omega^2 M phi restricted to H phi = 0 — Craig-Bampton's fixed
/// interface for a distributing (RigidFit) attachment, whose coordinates are
/// the six fitted motions a = H u (doc/theory.md §11.3). Null: none.
struct ModeConstraints {
  Teuchos::RCP<const MultiVector> F, Y;
};

/// What a cut-off's Sturm count says of the modes asked for: at least
/// `atLeast` eigenvalues lie below omega2 (rad/s squared). Anasazi's values
/// are checked against it (a miss is retried once, then an error); LAPACK's
/// need no check. atLeast < 0: no count.
struct SturmCut {
  double omega2 = 0.0;
  int atLeast = -1;
};

RitzBasis fixedInterfaceModes(const substructure::Substructure& s, const std::vector<GlobalOrdinal>& held,
                              int count, double eigensolverTolerance, double dependenceTolerance,
                              const ModeConstraints& constraints = {}, const SturmCut& cut = {});

}  // namespace cms::reduction
