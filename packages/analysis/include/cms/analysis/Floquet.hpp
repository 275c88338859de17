// Floquet analysis of a linear periodic system x' = A(t) x, A(t + T) = A(t)
// (doc/theory.md §16): what stays periodic when the rotor cannot be put into
// constant coefficients (two blades, an anisotropic support, a dissimilar
// blade), or on request as a check of the multi-blade path.
//
// The split follows Anasazi's: the *problem* (PeriodicSystem: the period, the
// state matrix as a callable, and which quantities are fixed-frame), the
// *analysis* (FloquetAnalysis: options validated against
// getValidParameters()) and the *result* (FloquetResult: monodromy matrix,
// multipliers, exponents, fixed-frame frequencies, each with its error
// estimate). Not converging to the requested tolerance is a status
// (FloquetResult::converged), never an exception.
//
// The monodromy matrix Phi(T) (Phi' = A Phi, Phi(0) = I) is integrated by the
// 4-stage Gauss-Legendre implicit Runge-Kutta method (order 8, A-stable,
// symplectic) with fixed steps; the error is estimated by comparing with the
// run at half the steps (Richardson: err(n) ~ ||Phi_n - Phi_{n/2}|| / (2^8 - 1)),
// and the steps are doubled until it meets "Tolerance" or "Maximum Steps Per
// Period" is reached. Multipliers mu = eigenvalues of Phi(T) (LAPACK dgeev);
// exponents rho = ln(mu) / T (principal log: |Im rho| <= pi / T); the fixed-frame
// frequency omega = Im rho + k 2 pi / T with k the dominant harmonic of the
// periodic part of the Floquet solution as seen through the observation (§16.3).
#pragma once

#include <complex>
#include <functional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include "cms/core/DenseMatrix.hpp"
#include "cms/eigen/GyroscopicSystem.hpp"

namespace cms::analysis {

/// M(t) q'' + D(t) q' + K(t) q = 0 at one instant: dense, n x n each, M
/// nonsingular (not necessarily symmetric).
struct SecondOrderMatrices {
  DenseMatrix M, D, K;
};

/// The same constant system for the eigen layer: M and the symmetric parts
/// of D and K (damping D, stiffness K), their skew parts G (Coriolis) and N
/// (circulatory), exactly symmetric / skew.
eigen::GyroscopicSystem gyroscopicSystem(const SecondOrderMatrices& m);
/// A linear T-periodic system x' = A(t) x of dimension n.
struct PeriodicSystem {
  double period = 0.0;  ///< T > 0 (s)
  int dimension = 0;    ///< n, the state's size
  /// A(t), n x n; called at arbitrary t in [0, T] (only there).
  std::function<DenseMatrix(double)> stateMatrix;
  /// C(t), p x n: the fixed-frame quantities y = C(t) x whose harmonic content
  /// picks a multiplier's frequency branch (§16.3). Empty: the state itself
  /// (y = x), right when every coordinate is fixed-frame. For a rotor, the
  /// multi-blade coordinates of the blades (MultiBladeTransform::inverse) and
  /// the fixed coordinates as they are.
  std::function<DenseMatrix(double)> observation;

  /// x = [q; q'], A = [[0, I], [-M^-1 K, -M^-1 D]]; `observation` (optional)
  /// returns p x n on the positions q only (lifted to [C, 0]).
  static PeriodicSystem secondOrder(double period, int n, std::function<SecondOrderMatrices(double)> matrices,
                                    std::function<DenseMatrix(double)> observation = {});

  /// Throws cms::InputError naming what is wrong: T not positive and finite,
  /// n < 1, no state matrix.
  void validate() const;
};

/// One characteristic multiplier and what follows from it.
struct FloquetMultiplier {
  std::complex<double> multiplier;  ///< mu, eigenvalue of the monodromy matrix
  std::complex<double> exponent;    ///< rho = ln(mu) / T, principal branch
  double growthRate = 0.0;          ///< Re rho (1/s): > 0 grows
  /// Estimated error of growthRate (1/s): kappa (||dPhi|| + n eps ||Phi||) / (|mu| T),
  /// kappa = ||u|| ||v|| / |u^H v| the multiplier's condition number (left u, right v).
  double growthRateError = 0.0;
  /// omega = Im rho + harmonic 2 pi / T (rad/s): the frequency in the fixed
  /// frame (may be negative: the conjugate member of a pair).
  double frequency = 0.0;
  int harmonic = 0;            ///< k of the principal-branch rule
  double harmonicShare = 0.0;  ///< energy of harmonic k over all harmonics, in (0, 1]: 1 is unambiguous
  double conditionNumber = 0.0;  ///< kappa above (1 for a normal monodromy matrix)
  double residual = 0.0;       ///< ||Phi v - mu v|| / (||Phi|| ||v||)
  std::vector<std::complex<double>> eigenvector;  ///< v (x(0) of the Floquet solution), ||v|| = 1
  /// lambda = Re rho + i omega: the exponent on the fixed-frame branch, what a
  /// constant-coefficient (multi-blade) eigenvalue would be.
  std::complex<double> fixedFrameExponent() const { return {growthRate, frequency}; }
};

enum class FloquetStability {
  Stable,    ///< every growth rate below minus its error
  Marginal,  ///< the largest growth rate within its error of 0 (an undamped system)
  Unstable   ///< some growth rate above its error
};
const char* toString(FloquetStability s);

struct FloquetResult {
  DenseMatrix monodromy;   ///< Phi(T)
  int steps = 0;           ///< steps per period of the reported Phi(T)
  /// ||Phi_n - Phi_{n/2}||_F / ((2^8 - 1) ||Phi_n||_F): relative error estimate of Phi(T).
  double monodromyError = 0.0;
  bool converged = false;  ///< monodromyError <= "Tolerance"
  /// Not converged because the estimate, below sqrt(eps), stopped falling
  /// when the steps were doubled: the rounding floor is above "Tolerance".
  bool stalled = false;
  /// |ln|det Phi(T)| - int_0^T tr A dt| (Liouville), relative to int |tr A| + 1:
  /// a check of the integration independent of the error estimate.
  double liouvilleDefect = 0.0;
  /// Sorted by decreasing growth rate (then frequency).
  std::vector<FloquetMultiplier> multipliers;
  double largestGrowthRate = 0.0;       ///< max Re rho (1/s)
  double largestGrowthRateError = 0.0;  ///< its growthRateError
  FloquetStability stability = FloquetStability::Stable;
  std::string integrator;  ///< what ran
  double maxResidual() const;
};

class FloquetAnalysis {
public:
  /// "Steps Per Period" (64): first number of steps (even, >= 2).
  /// "Maximum Steps Per Period" (16384): the doubling stops here (converged = false).
  /// "Tolerance" (1e-12): relative monodromy error to reach; the
  ///   default sits above the n eps rounding of a few hundred steps.
  /// The harmonic rule samples the observation at the reported run's steps:
  /// it resolves harmonics |k| < steps / 2.
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();
  explicit FloquetAnalysis(const Teuchos::ParameterList& params = Teuchos::ParameterList());

  /// Monodromy, multipliers, exponents, frequencies, stability of `system`.
  /// Throws InputError for an invalid system, NumericalError when A(t) is
  /// not finite or (second order) M(t) is singular, naming t.
  FloquetResult analyse(const PeriodicSystem& system) const;

  /// Called after each run of the doubling with a line saying the steps,
  /// the error estimate against the tolerance, and the seconds so far (a
  /// large model's runs take minutes).
  void setProgress(std::function<void(const std::string&)> progress) { progress_ = std::move(progress); }

  /// Phi(T) with exactly `steps` Gauss-Legendre steps (for convergence studies).
  static DenseMatrix monodromy(const PeriodicSystem& system, int steps);

private:
  int steps_, maxSteps_;
  double tolerance_;
  std::function<void(const std::string&)> progress_;
};

}  // namespace cms::analysis
