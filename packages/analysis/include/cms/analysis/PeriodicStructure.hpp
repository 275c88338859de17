// A structure whose rotor spins in its own frame on an attachment that
// moves: blades on a hub on an airframe (doc/theory.md §16.8). The synthesis
// gives constant matrices in q_e = [airframe..., b, hub and blades...], b
// the hub's attachment motion in its own (rotating) axes; the structure
// ties b = R6(psi)^T A q (A: the airframe's attachment motion, fixed axes;
// psi = omega t, the hub azimuth). Substituting this time-dependent
// constraint gives the periodic system of the individual-blade coordinates
// q; for N >= 3 identical blades (a "Copies: N" item below the hub) the
// multi-blade transform (§16.2) makes it constant, and its eigenvalues are
// the fixed-frame ones; otherwise (N = 2, a flexible hub, dissimilar blades)
// the Floquet analysis of §16.1 answers, and it can check the multi-blade
// path on request.
//
// Anasazi's split again: the problem (this class: the matrices at any
// azimuth), options validated against validParameters(), and the result (a
// synthesis::StructureModes whose modes are the fixed-frame ones, their
// shapes the motion at psi = 0 in q_e, so that characterise() and expand()
// serve them).
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/analysis/Floquet.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::analysis {

struct PeriodicModes {
  synthesis::StructureModes modes;
  /// "multi-blade" (constant coefficients in the fixed frame) or "Floquet",
  /// and why.
  std::string method, reason;
  int blades = 0;  ///< N of the blades' multi-blade transform (0: none)
  /// max over M, D, K of ||A(psi) - A(0)||_F / ||A(0)||_F of the transformed
  /// matrices at three azimuths: rounding for a symmetric rotor.
  double constancyDefect = -1.0;
  double constancyTolerance = 0.0;  ///< what rounding allows
  /// "Check With Floquet" on the multi-blade path: max over the modes of
  /// |lambda_multi-blade - lambda_Floquet| / |omega_hub|; -1 not checked.
  double floquetDifference = -1.0;
  FloquetResult floquet;  ///< when Floquet ran (as the answer or the check)
};

class PeriodicStructure {
public:
  /// "Method": Auto (multi-blade when the transformed matrices are constant
  ///   to rounding, else Floquet), Multi-Blade (an error when they are not),
  ///   Floquet;
  /// "Check With Floquet" (false): on the multi-blade path, also run Floquet
  ///   and report the largest difference of the exponents;
  /// "Floquet" sublist: FloquetAnalysis's parameters.
  static Teuchos::RCP<const Teuchos::ParameterList> validParameters();

  /// `structure` with exactly one moving hub (synthesis::MovingHub) whose
  /// attachment hangs on coordinates outside every hub; `speeds` one per
  /// speed parameter (rad/s). Throws cms::InputError naming what is not
  /// supported (no moving hub, two of them, a hub at rest: omega = 0 is
  /// the constant-coefficient structure, solved as usual).
  PeriodicStructure(const synthesis::SynthesizedStructure& structure, std::vector<double> speeds);

  int size() const { return n_; }     ///< coordinates q (q_e without b)
  double hubSpeed() const { return omega_; }  ///< rad/s, relative to the airframe
  double period() const;              ///< 2 pi / |omega|
  /// M(psi) q'' + C(psi) q' + K(psi) q = 0 in the individual-blade
  /// coordinates, ordered [fixed..., blade 0 ..., blade N-1 ...] (the
  /// blades last when there are copies). Dense.
  SecondOrderMatrices individual(double psi) const;
  /// N >= 3 copied blades below the hub: their multi-blade transform applies.
  int blades() const { return blades_; }

  /// The lowest `numModes` fixed-frame modes (one of each conjugate pair).
  PeriodicModes solve(int numModes, const Teuchos::ParameterList& options = Teuchos::ParameterList()) const;

  /// Where the Floquet path says how its doubling goes (FloquetAnalysis::setProgress).
  void setProgress(std::function<void(const std::string&)> progress) { progress_ = std::move(progress); }

private:
  /// q_e = Z(psi) q in the permuted order: derivative r = 0, 1, 2 in psi.
  DenseMatrix embedding(double psi, int r) const;
  /// The model's highest frequency (rad/s), for Floquet's step count.
  double highestFrequency() const;
  /// A mode's q (permuted order) as q_e at psi = 0, normalised q_e^H M_e q_e = 1.
  std::vector<std::complex<double>> toExtended(const std::vector<std::complex<double>>& q) const;

  const synthesis::SynthesizedStructure& structure_;
  std::vector<double> speeds_;
  eigen::GyroscopicSystem system_;  ///< M_e, G_e, K_e, D_e at the speeds
  synthesis::MovingHub hub_;
  double omega_ = 0.0;
  int n_ = 0, ne_ = 0, blades_ = 0, perBlade_ = 0;
  /// Why the multi-blade transform has no blades (blades_ == 0): what the
  /// copies below the hub are, for the console and the results' reason.
  std::string noBlades_;
  /// order_[i]: the q_e coordinate of permuted q coordinate i (b excluded).
  std::vector<int> order_;
  /// q = L xi: each blade's coordinates in its own (turned) axes, so that
  /// every blade's are alike. Identity for turned Ritz bases (theory §15.2);
  /// for Full copies, each node's rows turned back by the copy's angle.
  DenseMatrix local_;
  /// A Full hub's own coordinates (permuted index, node, component) and,
  /// per row, the permuted indices of its node's triple (-1: held or absent):
  /// written in fixed axes through R(psi) (theory §16.8).
  std::vector<std::array<int, 3>> hubRows_;
  std::vector<int> hubPartner_;
  std::function<void(const std::string&)> progress_;
};

}  // namespace cms::analysis
