// What every gyroscopic eigensolver returns: eigenvalues of
//   (lambda^2 M + lambda (G + D) + K + N) q = 0   (seed eq. (19) with Q = 0; D, N: theory §13)
// with their modes, a residual per mode, a stability class per mode, and the
// name of the solver that ran and why (doc/theory.md, "Results").
#pragma once

#include <complex>
#include <string>
#include <vector>

namespace cms::eigen {

/// Classification of one eigenvalue lambda of a conservative gyroscopic system.
/// The spectrum is Hamiltonian (lambda, -lambda, conj(lambda), -conj(lambda)),
/// so any Re(lambda) != 0 means instability (doc/theory.md, "Stability").
enum class Stability {
  Stable,      ///< lambda = i omega, omega > 0: a stable oscillation
  RigidBody,   ///< |lambda| below the rigid-body tolerance: zero frequency
  Divergence,  ///< lambda real and positive: static (buckling-like) instability
  Flutter,     ///< Re lambda > 0 and Im lambda != 0: oscillatory instability
  Neutral,     ///< Re lambda > 0 but within what rounding can produce (a defective
               ///< cluster split by the solver): neither stable nor unstable can be decided
  Critical     ///< zero frequency because K(Omega) is singular at this speed, not at
               ///< rest: a critical speed (the edge of a divergence band). Set by the
               ///< synthesis-level check (analysis::checkZeroFrequencies), never by a solver
};
const char* toString(Stability s);

/// Outcome of a solve as a status, never an exception (cf. Anasazi::ReturnType).
enum class SolveStatus {
  Converged,       ///< every requested mode converged
  NotConverged,    ///< fewer modes than requested met the tolerance
  NumericalIssue   ///< a factorisation or the eigensolver broke down
};
const char* toString(SolveStatus s);

struct GyroscopicMode {
  std::complex<double> lambda;  ///< eigenvalue (1/s)
  double omega = 0.0;           ///< |Im lambda| (rad/s): the damped natural frequency
  double hz = 0.0;              ///< omega / (2 pi)
  double growthRate = 0.0;      ///< Re lambda (1/s): > 0 is unstable
  /// zeta = -Re(lambda) / |lambda| (0 for lambda = 0): the fraction of
  /// critical damping; < 0 is unstable. 0 to rounding for an undamped system.
  double dampingRatio = 0.0;
  /// delta = -2 pi Re(lambda) / |Im(lambda)| = 2 pi zeta / sqrt(1 - zeta^2):
  /// the log of the ratio of successive amplitude peaks. Infinite for a
  /// real (overdamped or divergent) lambda != 0, 0 for lambda = 0.
  double logDecrement = 0.0;
  Stability stability = Stability::Stable;
  /// Complex mode shape, normalised q^H M q = 1, phase such that its largest
  /// entry is real and positive. For the distributed solvers this holds only
  /// this rank's rows (in the row map's order).
  std::vector<std::complex<double>> q;
  double kineticEnergy = 0.0;  ///< |lambda|^2 q^H M q / 2, amplitude of the mass-normalised mode
  double strainEnergy = 0.0;   ///< q^H K q / 2 (K = K_V - K_T: negative parts mean softening)
  /// ||(lambda^2 M + lambda (G + D) + K + N) q|| / ((||K|| + ||N|| + |lambda| (||G|| + ||D||) + |lambda|^2 ||M||) ||q||),
  /// a normwise backward error: ~1e-16 for a mode exact to rounding.
  double residual = 0.0;
  /// The mode's own frequency scale, componentwise: sqrt(|q|^T |K| |q| /
  /// q^H M q) + |q|^T |G| |q| / q^H M q (|A| the entrywise absolute value).
  /// What rounding of K and G can do to this mode's eigenvalue: the
  /// rigid-body and cluster tests are relative to it, so a stiff part that
  /// the mode does not load (a Craig-Bampton mode at 1e4 times the frequency)
  /// does not hide the mode's own frequency (theory §4.3). 0: not computed
  /// (the system-wide scale is used).
  double scale = 0.0;
  /// How far rounding can have moved this eigenvalue, rad/s: the radius of
  /// the split (defective) cluster the stability verdict found it in,
  /// 10 eta^(1/k) s for multiplicity k (theory §4.3), 10 eta s for a simple
  /// one; 0 where no verdict was made. A free body's frame-rate triple is
  /// split this far about the spin rate (1e-4 rad/s on the spacecraft).
  double splitRadius = 0.0;
  /// A mode's growth-rate uncertainty, 1/s (the dense general and damped
  /// paths, and the sparse path from the full model's residual): the
  /// largest of ten times its eigenvalue error (below; capped at its own
  /// scale), or refinedError where set, the split of a near-defective pair 10 sqrt(eta_q) |lambda|
  /// (eta_q its componentwise backward error) where another eigenvalue is
  /// that near, and instabilityTol |lambda| (growthUncertainty).
  /// A growth rate beyond it is an instability (theory §13.3). 0: not
  /// computed (the scale is used).
  double growthTolerance = 0.0;
  /// The error bound of an eigenvalue refined by two-sided inverse
  /// iteration, 1/s (twoSidedBound; theory §13.3): a positive growth rate
  /// within ten times eigenvalueError is refined with its left vector, whose
  /// bound is tight on stiff rows where ||r|| ||q|| is not. 0: not refined.
  double refinedError = 0.0;
  /// A mode the zero tests took (below the Rigid Body Tolerance of the
  /// scale, or within a split zero's radius) that the dense solve refined
  /// alone and showed to oscillate (theory §4.3, "A zero shown nonzero"):
  /// it is classified by its growth, not as a zero. False elsewhere.
  bool shownNonzero = false;
  /// A damped (or circulatory) system's mode whose positive growth rate,
  /// above the Instability Tolerance, stays within its uncertainty (after
  /// the refinement, where it was refined; undecidedGrowth, theory §13.3):
  /// its stability is Neutral.
  /// Always false for a conservative system, whose Neutral modes are split
  /// defective clusters (theory §4).
  bool undecided = false;
  /// The first-order a-posteriori error of the eigenvalue, rad/s: ||r|| ||q||
  /// / |q^H (2 lambda M + G + D) q| (0: not computed).
  /// Meaningful for a simple eigenvalue; for a defective one the
  /// denominator vanishes and the bound grows past |lambda| (theory §4.3).
  double eigenvalueError = 0.0;
  /// The eigenvalue's reported error, rad/s: refinedError where the mode was
  /// refined (a bound), else eigenvalueError (first order); the JSON's
  /// `eigenvalue_error`, whose `eigenvalue_error_kind` says which.
  double reportedError() const { return refinedError > 0.0 ? refinedError : eigenvalueError; }
  /// The frequency scale of the block this mode was solved in when it is
  /// not the whole system's: the Schur complement on the coordinates the
  /// stiffness at rest does not reach (GyroscopicSystem::unrestrained,
  /// theory §4.3), rad/s. The rigid-body and stability tests are relative
  /// to it. 0: solved with the whole system.
  double blockScale = 0.0;
  /// The relative accuracy of that block's matrices: eps times the condition
  /// of K on the other coordinates, through which they were formed (and the
  /// prestress with them). The stability verdict counts it with the
  /// residual. 0: solved with the whole system.
  double blockError = 0.0;
};

/// The energy bound on a damped system's growth rates (theory §13.3, "The
/// energy bound"; energyBound in EnergyBound.hpp): where shown, no
/// eigenvalue of the system has Re lambda above `growth`.
struct EnergyBound {
  bool shown = false;
  double growth = 0.0;  ///< 1/s, the bound d where shown
  std::string note;     ///< what was shown, or why it was not
};

struct GyroscopicResult {
  std::vector<GyroscopicMode> modes;  ///< ascending |lambda|
  std::string solver;                 ///< which solver produced the modes
  std::string reason;                 ///< why that solver (e.g. the fallback's cause)
  SolveStatus status = SolveStatus::Converged;
  int numRequested = 0;
  int iterations = 0;     ///< restarts/iterations of an iterative solver, 0 for dense
  int numOperatorApplies = 0;
  /// A damped dense solve's energy bound (not set: no bound was sought, as
  /// on the sparse path, whose full K is not factored by Cholesky).
  EnergyBound energyBound;
  double maxResidual() const;
  bool isStable() const;  ///< no Divergence or Flutter mode among those returned
  /// The least damping ratio over the modes that are not RigidBody or
  /// Critical (zero frequency): the stability margin of a damped structure
  /// (< 0: unstable); 0 when there is no such mode.
  double leastDampingRatio() const;
};

}  // namespace cms::eigen
