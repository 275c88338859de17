// Dense gyroscopic eigensolver for reduced models (up to a few thousand DOFs).
//
// Method "Meirovitch" (seed eqs. (20)-(24)): with I* = diag(M, K) = L L^T and
// G* = [[G, K], [-K, 0]], the problem omega^2 I* y = G*^T I*^-1 G* y is real
// symmetric with every omega^2 double. K' = L^-1 K* L^-T = A^T A where
// A = L^-1 G* L^-T is skew, so omega are the singular values of A: we take the
// SVD of A (error ~ eps ||A||) rather than eigenvalues of A^T A (which would
// square the condition number). Valid only for K > 0 (doc/theory.md, "Dense").
//
// Method "General": LAPACK dggev on the 2n first-order pencil, valid for any
// symmetric K; it returns complex lambda, and each mode is classified stable,
// rigid, divergent or fluttering.
//
// Method "Auto" (default): Meirovitch when the Cholesky factorisation of K
// succeeds with healthy pivots and the system is undamped (no D, N),
// otherwise General, saying why in the result.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include "cms/eigen/GyroscopicModes.hpp"
#include "cms/eigen/GyroscopicSolverManager.hpp"
#include "cms/eigen/GyroscopicSystem.hpp"

namespace cms::eigen {

/// The dense manager (GyroscopicSolverManager.hpp): every mode of a
/// replicated system, or the lowest "Number of Modes".
class DenseGyroscopicSolver : public GyroscopicSolverManager<GyroscopicSystem> {
public:
  /// Keys, types, defaults and one-line docs (print them with `print()`).
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();
  explicit DenseGyroscopicSolver(const Teuchos::ParameterList& params = Teuchos::ParameterList())
      : GyroscopicSolverManager(params, *getValidParameters(), "DenseGyroscopicSolver") {}
  GyroscopicResult solve(const GyroscopicSystem& system) const override;
};

/// Residual, energies, phase normalisation and stability class of modes whose
/// lambda and q are set (q unnormalised). Shared by every dense extraction.
/// `ownScales`: set GyroscopicMode::scale (for a solver whose accuracy is
/// componentwise per mode, e.g. Meirovitch's); otherwise 0, and the modes are
/// judged on the system's normwise scale.
/// `unreturned`: the solve's eigenvalues (Im >= 0) past those returned, for
/// classifyModes' mirror test.
void completeDenseModes(const GyroscopicSystem& system, std::vector<GyroscopicMode>& modes,
                        double rigidBodyTol, double instabilityTol, bool ownScales = false,
                        const std::vector<std::complex<double>>& unreturned = {});

/// The frequency scale sqrt(||K||/||M||) + ||G||/||M|| that the rigid-body and
/// instability tolerances are relative to.
double frequencyScale(double normM, double normG, double normK);

/// The uncertainty of a computed eigenvalue's growth rate
/// (GyroscopicMode::growthTolerance, theory §13.3): the largest of its
/// eigenvalue's error bound `errorBound` (ten times the first-order error of
/// a mode as solved; a refined mode's twoSidedBound), instabilityTol
/// |lambda|, and, only
/// where another eigenvalue lies within 100 sqrt(eta) |lambda| (a
/// near-defective pair that rounding splits by up to 10 sqrt(eta) |lambda|),
/// 10 sqrt(eta) |lambda|, eta = max(etaQ, eps) the mode's componentwise
/// backward error. The neighbours: `others` (every other computed
/// eigenvalue, Im >= 0) and their conjugates, lambda's own conjugate, and
/// for a `conservative` system the Hamiltonian mirrors -conj of all these and
/// of lambda itself. An isolated eigenvalue's error is first order in eta:
/// the split term on every mode read a damped rotor's growth of 6e-7
/// |lambda|, an eigenvalue 4e-3 |lambda| from any other, as "stable" at one
/// speed and FLUTTER at the next.
double growthUncertainty(std::complex<double> lambda, double errorBound, double etaQ, double instabilityTol,
                         const std::vector<std::complex<double>>& others, bool conservative);

/// Whether `m`'s growth rate is undecided and is refined (theory §13.3):
/// positive, above instabilityTol |lambda| but within its growthTolerance,
/// |lambda| above `zeroBelow` (a zero the rigid test takes anyway; a first
/// version also asked for a first-order error below |lambda|, for split
/// zeros, and a stiff rotor's 0.0147 1/s flutter within 1172 read "stable":
/// a review),
/// not solved apart (blockScale), and no other of `modes` (or a mirror)
/// within 1e-3 |lambda|: a split cluster's member (a free body's frame-rate
/// triple at i Omega, split by rounding by ~1e-4 Omega), of which inverse
/// iteration would pick one as rounding decides (the rank counts' values
/// differed: the campbell rank test).
bool undecidedGrowth(const GyroscopicMode& m, const std::vector<GyroscopicMode>& modes, double instabilityTol,
                     double zeroBelow);

/// Whether a damped mode's eigenvalue is not shown within frequencyTol
/// |lambda| by its first-order error (theory §5, "Stiff rows"): its
/// residual, small against ||K||, is not small against the stiffness its own
/// coordinates see where a stiff part is coupled to a soft one. A support of
/// E = 1e18 under a steel shaft left the shaft's damped frequencies 4e-5
/// off on the sparse path (1e-3 at other mode counts), 1e-2 on the dense
/// path, with normwise residuals of 1e-14 and no error said. Not a zero
/// (below `zeroBelow`), not one solved apart. Both paths refine such a mode.
bool uncertainFrequency(const GyroscopicMode& m, double frequencyTol, double zeroBelow);

/// A damped set's eigenvalue accuracy, for the reason (theory §5, "Stiff
/// rows"): "; k mode(s) refined<where> by two-sided inverse iteration, each
/// eigenvalue within e of |lambda| (bound)" for the refined ones, and
/// "; u mode(s) not shown within the Frequency Tolerance t (worst: mode j, e
/// of |lambda|)" for those whose reported error (GyroscopicMode::
/// reportedError) still exceeds frequencyTol |lambda|. Zeros and modes
/// solved apart have no relative accuracy to say. Empty if neither.
std::string accuracyNote(const std::vector<GyroscopicMode>& modes, double frequencyTol, const std::string& where);

/// The two-sided Rayleigh functional (theory §13.3): the root nearest `near`
/// of y^H Q(mu) x = a mu^2 + b mu + c = 0, with a = y^H M x, b = y^H (G + D) x,
/// c = y^H (K + N) x for a right vector x and a left vector y, by the
/// quadratic formula without cancellation. NaN when a = b = 0.
std::complex<double> twoSidedRoot(std::complex<double> a, std::complex<double> b, std::complex<double> c,
                                  std::complex<double> near);

/// What rounding the two-sided functional's coefficients carry, for
/// twoSidedBound: for A = K + N, G + D, M (in that order), sum_i m_i |y_i|
/// (|A| |x|)_i with m_i the nonzeros of A's row i, and |y|^T |A x|; and the
/// system's order n.
struct FunctionalRounding {
  double absolute[3] = {0.0, 0.0, 0.0};
  double product[3] = {0.0, 0.0, 0.0};
  double n = 0.0;
};

/// The error bound of an eigenvalue refined by two-sided inverse iteration
/// (theory §13.3), 1/s: what rounding the functional's coefficients can
/// carry (below) once the last step's change of lambda, `change`, is within
/// it; before that, the error left after contraction at the last ratio r =
/// change / changeBefore, change r / (1 - r) (the shift is fixed, so the
/// iteration converges linearly; infinite if the changes do not shrink:
/// undecided). The rounding (Higham, Accuracy and
/// Stability of Numerical Algorithms, §3.5: row i of a product A x with m_i
/// nonzeros errs by m_i eps (|A| |x|)_i, the n-term sum y^H (A x) by n eps
/// |y|^T |A x|; twice each for the complex parts),
///   2 eps sum_A w_A (sum_i m_i |y_i| (|A| |x|)_i + n |y|^T |A x|) / |2 lambda a + b|,
/// w = 1, |lambda|, |lambda|^2 for K + N, G + D, M, and 2 lambda a + b =
/// y^H Q'(lambda) x. The left vector makes it tight where ||r|| ||q|| is
/// not: the residual of a stiff row, where x and y are small, does not
/// reach the eigenvalue.
double twoSidedBound(std::complex<double> lambda, double change, double changeBefore, std::complex<double> a,
                     std::complex<double> b, const FunctionalRounding& rounding);

/// The two-sided iteration's eigenvalue and its last two changes, as both
/// refinements (dense and sparse) keep them for twoSidedBound.
struct TwoSidedEstimate {
  std::complex<double> lambda;
  double change = 0.0, changeBefore = 0.0;
  /// One step: lambda <- twoSidedRoot(a, b, c, lambda), the changes
  /// shifted. Returns whether lambda stays finite.
  bool step(std::complex<double> a, std::complex<double> b, std::complex<double> c);
  /// The same, the root nearest `near` (a block's Ritz value: refineModes).
  bool step(std::complex<double> a, std::complex<double> b, std::complex<double> c, std::complex<double> near);
};

/// Which step of a two-sided refinement stands, and with what bound (theory
/// §5, "Stiff rows"; the dense and the sparse refinement alike). A close
/// pair refined from a shift between its members stalls at a weighted mean
/// of the two, each step moving it by less than the rounding floor, and that
/// floor would be claimed for a value far from either member. So a step's
/// twoSidedBound stands only where the residual weighed by the left vector
/// agrees with it to first order, measure = sum_i |y_i| |(Q(lambda) x)_i| /
/// |y^H Q'(lambda) x| <= bound; or, where the measure at least halves from
/// the step before (a close neighbour's leftover damped by a constant
/// ratio), with the measure as its bound. Not at the first two steps, which
/// cannot show a drift, nor where the value drifts steadily: two changes of
/// ratio 0.8-1.25 in one direction (the value two steps back more than 1.5
/// changes away). The least standing bound is kept.
class RefinementGate {
 public:
  explicit RefinementGate(std::complex<double> start) : bestLambda(start), oneBack_(start), twoBack_(start) {}
  /// Step `step` (0, 1, ...) of `e`, just taken, with its twoSidedBound and
  /// measure: whether it stands with the least bound so far (then `best` and
  /// `bestLambda` are its).
  bool offer(int step, const TwoSidedEstimate& e, double bound, double measure);
  double best = std::numeric_limits<double>::infinity();
  std::complex<double> bestLambda;

 private:
  double previousMeasure_ = std::numeric_limits<double>::infinity();
  std::complex<double> oneBack_, twoBack_;
};

/// Classify lambda against the tolerances (relative to `scale`).
Stability classify(std::complex<double> lambda, double scale, double rigidBodyTol,
                   double instabilityTol);

/// The stability of every mode, decided against what rounding can do to its
/// eigenvalue (doc/theory.md, "Stability within round-off"): a cluster of k
/// eigenvalues (counting the Hamiltonian mirrors -lambda, conj(lambda) of the
/// returned ones; k <= 4, and at most 2k values within the radius) may be a
/// defective eigenvalue that a backward
/// stable solver splits by up to 10 (max(eta, eps))^(1/k) s, with eta the
/// mode's backward error and s the frequency scale. Within that radius of
/// zero a mode is RigidBody; a positive growth rate within it is Neutral, not
/// Flutter or Divergence; beyond it (and beyond instabilityTol s) unstable.
/// `conservative` = false (a damped system, D or N present): the spectrum is
/// not Hamiltonian, there is no mirror to pair with, and each mode is
/// classified by `classify` alone (Re lambda above instabilityTol s is unstable).
/// `completeShapes`: every mode's q holds all its rows (the dense path), so
/// a cluster of k >= 3 values counts as a split defective eigenvalue only
/// when two of them have nearly parallel shapes (theory §4); false for
/// distributed shapes (the sparse path), which cannot be compared alike on
/// every rank. `unreturned`: eigenvalues the solve found past the returned
/// modes (the count can cut a flutter quadruple's a + ib from its mirror
/// -a + ib, of equal |lambda|); a growing mode's mirror among them counts.
void classifyModes(std::vector<GyroscopicMode>& modes, double scale, double rigidBodyTol,
                   double instabilityTol, bool conservative = true, bool completeShapes = false,
                   const std::vector<std::complex<double>>& unreturned = {});

/// dampingRatio and logDecrement of a mode from its lambda.
void setDamping(GyroscopicMode& mode);
/// A mode labelled RigidBody gets damping ratio and log decrement 0: its
/// lambda is zero to rounding, whose -Re/|lambda| is +-1, not a ratio.
void zeroRigidDamping(GyroscopicMode& mode);

}  // namespace cms::eigen
