// The Campbell study: a speed sweep of a spinning structure with its modes
// tracked across speeds, in the Anasazi style (doc/theory.md §12):
//
//   SpeedSweepProblem   what is swept (the data): the speed parameters and, at
//                       given speeds, the modes, their M-weighted MAC with
//                       another speed's modes and their whirl. Two kinds:
//                       DenseSweepProblem (M, G1, K0, K2 of one speed, e.g. a
//                       Rayleigh shaft) and SynthesizedSweepProblem (a
//                       synthesised structure, every spin rate a parameter,
//                       no re-projection).
//   CampbellStudy       the solver, configured by a ParameterList validated
//                       against getValidParameters() (Title Case keys with
//                       defaults): sweep, tracking, crossings, stability.
//   CampbellResult      what it found: tracks, engine-order crossings
//                       (critical speeds), frame-rate tracks set aside,
//                       unstable ranges, the worst solve status.
//
// Tracking: the modes at each speed are matched to the tracks by decreasing
// M-weighted MAC |a^H M b|^2 / (a^H M a b^H M b) with the track's mode at
// the previous speed, so a crossing keeps its identities (the curves cross)
// and a veering too (the curves turn away; the eigenvectors rotate over the
// veering, which the sweep must resolve).
#pragma once

#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/analysis/WhirlClassification.hpp"
#include "cms/analysis/ZeroFrequencies.hpp"
#include "cms/core/DenseMatrix.hpp"
#include "cms/eigen/GyroscopicModes.hpp"
#include "cms/eigen/GyroscopicSystem.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::analysis {

/// A system of one speed Omega stored per unit speed (theory §8):
///   M q'' + Omega G1 q' + (K0 + Omega^2 K2) q = 0,
/// K2 = K_sigma1 - K_T1 in a rotating frame, empty (0 x 0) for none.
struct SpeedDependentSystem {
  DenseMatrix M, G1, K0, K2;
  /// (v, w) coordinate pairs of two transverse directions (e1 x e2 = the spin
  /// axis) whose orbit tells forward from backward whirl.
  std::vector<std::pair<int, int>> whirlPairs;
  /// Viscous damping, independent of speed (theory §13); 0 x 0 for none.
  DenseMatrix D;

  eigen::GyroscopicSystem at(double Omega) const;
};

/// What a Campbell study needs of a model. Every method is collective.
class SpeedSweepProblem {
public:
  virtual ~SpeedSweepProblem() = default;
  /// The spin rates that can be swept (name, nominal rad/s).
  virtual std::vector<synthesis::SpeedParameter> parameters() const = 0;
  /// The modes at one set of speeds (rad/s, one per parameter).
  virtual synthesis::StructureModes solve(const std::vector<double>& speeds) const = 0;
  /// The modes at every set of speeds, in order: solve() one after
  /// another, unless a problem can do better (`threads` as
  /// SynthesizedStructure::solveMany: 0 for the cores left to this rank).
  virtual std::vector<synthesis::StructureModes> solveAll(const std::vector<std::vector<double>>& speeds,
                                                          int threads) const {
    (void)threads;
    std::vector<synthesis::StructureModes> out;
    for (const auto& s : speeds) out.push_back(solve(s));
    return out;
  }
  /// M-weighted MAC of every pair (a[t], b[j]), rows t.
  virtual std::vector<std::vector<double>> mac(const std::vector<eigen::GyroscopicMode>& a,
                                               const std::vector<eigen::GyroscopicMode>& b) const = 0;
  /// Whirl of every mode of `modes` (solved at modes.speeds).
  virtual std::vector<Whirl> whirl(const synthesis::StructureModes& modes, const WhirlClassification& rule) const = 0;
  /// The same with each mode's forward part (WhirlClassification::classify's
  /// forwardShare: an elliptical backward orbit's share that unbalance
  /// excites); by default none known (-1).
  virtual std::vector<Whirl> whirlAndForwardShare(const synthesis::StructureModes& modes, const WhirlClassification& rule,
                                                  std::vector<double>& forwardShare) const {
    auto w = whirl(modes, rule);
    forwardShare.assign(w.size(), -1.0);
    return w;
  }
  /// The part whose orbit defines whirl ("" when none).
  virtual std::string whirlOf() const = 0;
  /// True when that part's orbits are seen from a spinning frame in which
  /// its unbalance is no 1X force of the reference rate (parameter
  /// `reference`): its own frame (an A with Frame: Rotating, where its
  /// unbalance is static), or a spinning parent's frame (a spinning C, a
  /// rotating-frame A) when its own rate is not the reference (a disc on a
  /// spinning shaft C, swept by the shaft's rate).
  virtual bool whirlInRotorFrame(int reference) const {
    (void)reference;
    return false;
  }
  /// Per mode of `modes`, the part that carries the largest share of its
  /// kinetic energy (a substructure's name; theory §11.6).
  virtual std::vector<std::string> dominant(const synthesis::StructureModes& modes) const = 0;
  /// How many eigenvalues of the stiffness K(speeds) (spin softening and
  /// stress stiffening included) are negative: where the count changes, K
  /// is singular and a frequency passes through zero (theory §12.1).
  /// `negative` -1 with `why` where no count is made (this default; a
  /// free body, whose K is singular at every speed; a rotor on a moving
  /// hub). A pivot within rounding of zero (1e-13 of its row's own
  /// stiffness) is not counted negative.
  virtual StiffnessCount stiffnessCount(const std::vector<double>& speeds) const {
    (void)speeds;
    StiffnessCount none;
    none.available = false;
    none.why = "the model gives no stiffness count";
    return none;
  }
};

/// One speed, dense: eigen::DenseGyroscopicSolver with `solverParams`.
class DenseSweepProblem : public SpeedSweepProblem {
public:
  DenseSweepProblem(SpeedDependentSystem system, std::string name, double nominal,
                    const Teuchos::ParameterList& solverParams = Teuchos::ParameterList());
  std::vector<synthesis::SpeedParameter> parameters() const override { return {{name_, nominal_}}; }
  synthesis::StructureModes solve(const std::vector<double>& speeds) const override;
  std::vector<std::vector<double>> mac(const std::vector<eigen::GyroscopicMode>& a,
                                       const std::vector<eigen::GyroscopicMode>& b) const override;
  std::vector<Whirl> whirl(const synthesis::StructureModes& modes, const WhirlClassification& rule) const override;
  std::vector<Whirl> whirlAndForwardShare(const synthesis::StructureModes& modes, const WhirlClassification& rule,
                                          std::vector<double>& forwardShare) const override;
  std::string whirlOf() const override { return system_.whirlPairs.empty() ? "" : name_; }
  /// One part: `name` for every mode.
  std::vector<std::string> dominant(const synthesis::StructureModes& modes) const override {
    return std::vector<std::string>(modes.result.modes.size(), name_);
  }
  StiffnessCount stiffnessCount(const std::vector<double>& speeds) const override;

private:
  SpeedDependentSystem system_;
  std::string name_;
  double nominal_;
  Teuchos::ParameterList solverParams_;
};

/// A synthesised structure: every speed parameter of the assembly, solved by
/// SynthesizedStructure::solve with `solveParams` (its valid parameters).
/// Whirl of substructure `whirlOf` (a spinning A or R; "" the first one).
class SynthesizedSweepProblem : public SpeedSweepProblem {
public:
  SynthesizedSweepProblem(const synthesis::AssembledStructure& structure, const synthesis::SynthesizedStructure& reduced,
                          const Teuchos::ParameterList& solveParams, const std::string& whirlOf = "");
  std::vector<synthesis::SpeedParameter> parameters() const override { return reduced_.speeds(); }
  synthesis::StructureModes solve(const std::vector<double>& speeds) const override;
  /// SynthesizedStructure::solveMany: the dense solves on threads.
  std::vector<synthesis::StructureModes> solveAll(const std::vector<std::vector<double>>& speeds,
                                                  int threads) const override;
  std::vector<std::vector<double>> mac(const std::vector<eigen::GyroscopicMode>& a,
                                       const std::vector<eigen::GyroscopicMode>& b) const override;
  std::vector<Whirl> whirl(const synthesis::StructureModes& modes, const WhirlClassification& rule) const override;
  std::vector<Whirl> whirlAndForwardShare(const synthesis::StructureModes& modes, const WhirlClassification& rule,
                                          std::vector<double>& forwardShare) const override;
  std::string whirlOf() const override;
  bool whirlInRotorFrame(int reference) const override;
  /// By SynthesizedStructure::characterise's kinetic shares; parts whose
  /// shares agree with the largest to 1e-3 are named together, "a & b"
  /// (identical parts in a symmetric mode).
  std::vector<std::string> dominant(const synthesis::StructureModes& modes) const override;
  /// Dense L D L^T of K up to "Dense Limit" coordinates, else the sparse
  /// inertia (cms::inertia), K scaled by its diagonal first; not counted
  /// for a free-floating structure or a moving hub.
  StiffnessCount stiffnessCount(const std::vector<double>& speeds) const override;

private:
  const synthesis::AssembledStructure& structure_;
  const synthesis::SynthesizedStructure& reduced_;
  Teuchos::ParameterList solveParams_;
  Teuchos::RCP<const CrsMatrix> M_;
  int whirlPart_ = -1;  ///< substructure index, -1 none
  int whirlSpeed_ = -1; ///< index of the speed parameter its spin rate scales with, -1 none
};

/// M-weighted MAC of every pair (a[t], b[j]) of modes of the same
/// coordinates, each mode's q replicated (n entries) or this rank's rows of
/// M's row map. Collective.
std::vector<std::vector<double>> macMatrix(const CrsMatrix& M, long long n, const std::vector<eigen::GyroscopicMode>& a,
                                           const std::vector<eigen::GyroscopicMode>& b);

/// One mode followed across the sweep.
struct CampbellTrack {
  std::vector<double> omega;                  ///< rad/s per step; NaN where lost
  std::vector<eigen::Stability> stability;    ///< per step
  std::vector<Whirl> whirl;                   ///< per step
  /// Per step, the orbit's forward part (WhirlClassification::classify; -1
  /// where not known or lost).
  std::vector<double> forwardShare;
  std::vector<bool> lost;                     ///< no mode matched at this step
  std::vector<double> dampingRatio;           ///< per step, zeta = -Re lambda / |lambda| (NaN where lost)
  /// Per step, how far rounding can have moved the frequency (the mode's
  /// GyroscopicMode::splitRadius, rad/s; 0 where lost).
  std::vector<double> splitRadius;
  double minMac = 1.0;                        ///< worst MAC of a step-to-step match
  /// The step it starts at: 0, or where a mode entered the requested set
  /// mid-sweep (from above: its crossings before this step are not checked);
  /// lost before it.
  int firstStep = 0;
  /// Its frequency equals a spin rate (of parameter frameRateOf) at every
  /// step, within "Frame Rate Tolerance" times the rate plus the step's
  /// splitRadius: a rigid motion seen from a frame spinning at that rate,
  /// not a vibration; its engine-order crossings are no critical speeds.
  bool frameRate = false;
  int frameRateOf = -1;
};

/// Where a track meets an engine-order line omega = order * |Omega_ref|.
struct EngineOrderCrossing {
  double order = 1.0;
  double speed = 0.0;      ///< Omega_ref (rad/s)
  double factor = 0.0;     ///< on the sweep's factor axis
  double omega = 0.0;      ///< = order * |speed| (rad/s): the excitation frequency, a negative rate turning against its axis
  Whirl whirl = Whirl::Neutral;
  /// Its orbit's forward part, 0 (a backward circle) .. 1 (a forward one);
  /// -1 not known. Unbalance excites a backward whirl through it where
  /// anisotropy makes the orbit an ellipse.
  double forwardShare = -1.0;
  std::vector<int> tracks; ///< several: identical parts (or a repeated mode), listed once
  /// Per entry of `tracks`: the substructure that carries most of that
  /// track's kinetic energy at the crossing (for identical parts, each copy).
  std::vector<std::string> dominant;
  bool refined = false;    ///< by bisection (else linear between sweep speeds)
};

/// The units an engineer reads a Campbell diagram in: the reference speed
/// in rev/s and frequencies in Hz (Hz), the speed in rpm and frequencies in
/// Hz (Rpm), or frequencies as multiples of the reference speed (PerRev:
/// engine orders are horizontal lines).
enum class SpeedAxis { Hz, Rpm, PerRev };
/// "hz", "rpm", "per-rev"; cms::InputError naming `option` otherwise.
SpeedAxis speedAxis(const std::string& text, const std::string& option = "--axis");
const char* toString(SpeedAxis a);

struct CampbellResult {
  std::vector<synthesis::SpeedParameter> parameters;
  int reference = 0;                 ///< the parameter whose rate the factors and engine orders refer to
  std::vector<bool> scaled;          ///< per parameter: swept (true) or held at its nominal value
  std::vector<double> factors;       ///< per step: the multiple of the nominal rates
  std::vector<std::vector<double>> speeds;  ///< [step][parameter] rad/s
  std::vector<CampbellTrack> tracks;
  std::vector<double> orders;        ///< the engine orders asked
  std::vector<EngineOrderCrossing> crossings;  ///< by order, then speed; frame-rate tracks left out
  /// A sign change of a track's omega - n Omega between two sweep speeds
  /// that bisection showed to be a jump between two branches (the tracking
  /// took another mode at the upper speed), followed from either end: no
  /// critical speed is read there, and a crossing of either branch in the
  /// interval may be missed (theory §12.3).
  struct BranchJump {
    int track = 0;
    double order = 1.0;
    double from = 0.0, to = 0.0;  ///< the sweep speeds around it, Omega_ref (rad/s)
  };
  std::vector<BranchJump> branchJumps;
  /// The crossings of frame-rate tracks that follow a held rate (met by an
  /// engine order of the swept one), bisected like the others but no
  /// critical speeds (a rigid motion seen at a spin rate): listed apart.
  std::vector<EngineOrderCrossing> frameRateCrossings;
  /// Sign changes of frame-rate tracks that follow a swept rate: such a
  /// track lies on an engine-order line at every speed and rounding puts it
  /// on either side. Counted; neither bisected nor listed.
  int frameRateOnLine = 0;
  std::vector<std::pair<double, double>> unstableRanges;  ///< Omega_ref (rad/s) where some mode is unstable
  /// The ranges' edges bisected between the grid's stable and unstable
  /// speeds to "Crossing Tolerance" ("Refine Crossings"); else the first and
  /// last unstable grid speeds, up to a step inside the band.
  bool unstableEdgesRefined = false;
  /// Per unstable range: (unstable at the sweep's first speed, at its last):
  /// that end is the sweep's, not an edge of the range, which goes on
  /// beyond it.
  std::vector<std::pair<bool, bool>> unstableOpen;
  /// Per unstable range: it holds a band the stiffness count proves
  /// divergent, an odd number of K's negative eigenvalues between two
  /// zero-frequency speeds (det K < 0: a real root lambda > 0, theory
  /// §12.1), whether or not a grid speed's solve showed it; its edges there
  /// the bisected zeros. Merged with a grid range it meets.
  std::vector<bool> unstableByCount;
  /// Per unstable range: the stretches (Omega_ref, rad/s) the count proves
  /// divergent inside it (empty: none).
  std::vector<std::vector<std::pair<double, double>>> unstableCountBands;
  /// Per unstable range: whether its lower and upper edges were bisected
  /// (the grid's edges with "Refine Crossings", a count band's always);
  /// else the grid's unstable speeds.
  std::vector<std::pair<bool, bool>> unstableEdgesBisected;
  /// Omega_ref (rad/s), first and last speed of each run of speeds where
  /// some mode's growth rate is undecided (GyroscopicMode::undecided: a
  /// damped structure's growth its uncertainty does not tell from the
  /// Instability Tolerance, "neutral" in the CSV; theory §13.3): the grid's
  /// runs, and per unstable edge the lowest to the highest speed its
  /// bisection met undecided, merged where they overlap; in the sweep's
  /// direction (from high to low for a negative nominal rate). Neither
  /// stable nor unstable there; not bisected themselves.
  std::vector<std::pair<double, double>> undecidedRanges;
  /// Reference speeds (rad/s) where a frequency passes through zero: the
  /// count of K(Omega)'s negative eigenvalues changes there, bisected on
  /// the count to "Crossing Tolerance" (always: a factorisation a step);
  /// none at rest. In a spinning frame a zero frequency is a static mode of
  /// that frame: in a rotor's own frame its unbalance critical speed.
  std::vector<double> zeroFrequencySpeeds;
  std::vector<bool> zeroFrequencyRefined;  ///< per speed: false where a count failed inside its bracket
  bool zeroCountsTaken = false;            ///< sought (the model gives counts)
  std::string zeroCountsNote;              ///< why not counted, or where a count failed
  std::string whirlOf;               ///< the part whose orbit defines whirl
  bool whirlInRotorFrame = false;    ///< SpeedSweepProblem::whirlInRotorFrame: no unbalance note then
  std::string solver;                ///< the solver at the last speed
  double maxResidual = 0.0;
  eigen::SolveStatus status = eigen::SolveStatus::Converged;  ///< the worst (NumericalIssue before NotConverged)
  std::string reason;                ///< of the worst status

  /// The table: one row per step (factor, the reference speed in `axis`'s
  /// unit, every rate in rad/s, each track's frequency (Hz, or per rev) and
  /// whirl; `*` an unstable or lost point). Rank 0 prints.
  void printTable(std::ostream& os, SpeedAxis axis = SpeedAxis::Rpm) const;
  /// Engine-order crossings (critical speeds) in rad/s and rpm, forward and
  /// backward told apart (unbalance excites forward whirl), identical parts
  /// once, each with the substructure that dominates its mode; then the
  /// frame-rate tracks and their crossings, and the unstable ranges.
  void printCrossings(std::ostream& os) const;
  /// CSV: factor, <parameter>_rad_per_s (the reference first), and per track
  /// track<i>_hz, track<i>_stability, track<i>_damping_ratio, track<i>_whirl,
  /// track<i>_frame_rate.
  void writeCsv(std::ostream& os) const;
  /// CSV of the crossings (critical speeds only): order, speed_rad_per_s,
  /// speed_rpm, frequency_hz, whirl, unbalance (yes: forward whirl at order
  /// 1), tracks (a;b), refined (yes: bisected), dominant (the substructure
  /// that dominates each track's mode there, a;b).
  void writeCrossingsCsv(std::ostream& os) const;
};

class CampbellStudy {
public:
  /// "Steps" (int, 21, >= 2): speeds in the sweep, factor 0 to "Max Factor";
  /// "Max Factor" (double, 2): top speed as a multiple of the nominal rates;
  /// "Speed Factor" (double, 1): the nominal rates times this first (a scene's);
  /// "Speed Parameter" (string, ""): the one parameter swept, the others held
  ///   at nominal; "" sweeps all together (the first is the reference);
  /// "Engine Orders" (Array(double), {1}): lines omega = order * Omega_ref;
  /// "Refine Crossings" (bool, true): bisect each crossing (one solve per step);
  /// "Crossing Tolerance" (double, 1e-6): relative bracket width that ends a bisection;
  /// "Frame Rate Tolerance" (double, 1e-3): relative difference within
  ///   which a track's frequency equals a spin rate;
  /// "Whirl" (sublist): WhirlClassification's parameters;
  /// "Threads" (int, 0): threads for the sweep's solves on each rank (0: the
  ///   cores left to it; the speeds are independent until tracked).
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();
  explicit CampbellStudy(const Teuchos::ParameterList& params = Teuchos::ParameterList());

  /// Collective. Throws cms::InputError for an unknown "Speed Parameter".
  /// A solve that does not converge or breaks down is a status of the
  /// result, not an exception.
  CampbellResult run(const SpeedSweepProblem& problem) const;

private:
  Teuchos::ParameterList params_;
};

}  // namespace cms::analysis
