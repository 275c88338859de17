// How many eigenfrequencies of a gyroscopic system lie below a frequency,
// counted from the inertia of one Hermitian factorisation rather than from
// any eigensolver (doc/theory.md, "Sturm count of a gyroscopic system").
#pragma once

#include "cms/eigen/GyroscopicSystem.hpp"

namespace cms::eigen {

/// The number of eigenfrequencies omega_j < omega (counted with multiplicity,
/// one per +/- pair) of M q'' + G q' + K q = 0 with M > 0 and K > 0: the number
/// of negative eigenvalues of the Hermitian Q(omega) = K - omega^2 M + i omega G.
/// Each eigencurve of Q starts positive (Q(0) = K > 0), ends negative and has
/// exactly one zero on (0, inf), so the inertia counts the crossings below
/// omega. Reliable while omega is farther from every eigenfrequency than
/// rounding (eps times the conditioning of Q) can move it. LAPACK zhetrf
/// (Bunch-Kaufman), n^3/3 complex operations. Throws NumericalError if the
/// factorisation fails; InputError if omega is not positive and finite.
int sturmCount(const GyroscopicSystem& sys, double omega);

}  // namespace cms::eigen
