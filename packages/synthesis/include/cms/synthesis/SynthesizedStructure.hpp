// Component-mode synthesis of a structure (doc/theory.md §11): every
// substructure's physical DOFs are written through an interface transform as
//
//   u_s = X_s a_s + V_s eta_s,    a_s = H_s u_parent(s)          (§11.2)
//
// (the rigid motion of its attachment frame, driven by the parent's own
// coordinates, plus its Ritz coordinates), so the structure's coordinates q
// are [w_OC, theta_C (free C only), eta of each substructure in tree order]
// and u_s = T_s q with a sparse T_s. The structure's matrices are
// sum_s T_s^T A_s T_s for every per-unit-speed piece A_s, kept apart per
// spin parameter so that a speed sweep does no re-projection:
//
//   G(s) = sum_i s_i G_i,     K(s) = K_0 + sum_{i<=j} s_i s_j K_ij.
//
// With Full bases (no truncation) the same code gives the truth model: the
// monolithic FE model with each attachment's DOFs slaved to its parent.
#pragma once

#include <complex>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/core/DenseMatrix.hpp"
#include "cms/core/TpetraTypes.hpp"
#include "cms/eigen/GyroscopicModes.hpp"
#include "cms/eigen/GyroscopicSystem.hpp"
#include "cms/eigen/SparseGyroscopicSystem.hpp"
#include "cms/reduction/RitzBasis.hpp"
#include "cms/synthesis/Structure.hpp"

namespace Teuchos { template <class T> class Comm; }
namespace cms::reduction { class StaticCorrection; }

namespace cms::substructure {
enum class Matrix;  // cms/substructure/Substructure.hpp
}

namespace cms::synthesis {

/// One spin rate of the structure: C's frame, or an R or A relative spin.
struct SpeedParameter {
  std::string name;      ///< the substructure that declares it
  double nominal = 0.0;  ///< rad/s
};

/// The substructures assembled (in parallel, with the centrifugal prestress
/// of each computed with its attachment held and its children's reactions
/// applied, leaves first: doc/theory.md §11.4) and their interfaces
/// resolved. Independent of the bases, so one assembly serves every
/// reduction strategy and the truth.
class AssembledStructure {
public:
  /// Collective. Throws cms::InputError naming the substructure for an
  /// inconsistent description (see StructureDescription::validate, plus:
  /// attachment nodes missing or without rotations, a RigidFit set that
  /// cannot fix a rotation, a combination with periodic coefficients).
  static AssembledStructure assemble(const StructureDescription& description,
                                     const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

  std::size_t numSubstructures() const { return parts_.size(); }
  /// The k-th substructure's description, tree order (pre-order from C).
  /// The copies of a "Copies: N" item are items of their own ("blade[2]"),
  /// each with SubstructureSpec::copy set.
  const SubstructureSpec& substructure(std::size_t k) const;
  /// A copy's prototype (copy 1 of the same item, whose reduction every copy
  /// shares: doc/theory.md §15); k itself for anything else.
  std::size_t prototypeOf(std::size_t k) const;
  /// Its held rows (attachment, or a free C's reference), sorted: a Full
  /// basis's coordinates are the other rows, in order.
  std::vector<long long> heldRows(std::size_t k) const;
  /// The point its frame follows (attachment point; a free C's reference
  /// point; a rigid rotor's centre). For a clamped C: the origin.
  fem::Vec3 attachmentPoint(std::size_t k) const;
  /// Its assembled matrices and DOF table (null for a rigid rotor).
  const substructure::Substructure* assembled(std::size_t k) const;

  struct Part;  ///< one substructure, assembled (AssembledStructure.cpp)
  const std::vector<std::shared_ptr<Part>>& parts() const { return parts_; }
  const std::vector<SpeedParameter>& speeds() const { return speeds_; }
  std::vector<double> nominalSpeeds() const;
  bool freeFloating() const { return free_; }
  /// Empty unless the structure is free-floating and, at these speeds, the
  /// rotors spinning relative to its frame (R, stationary-frame A) carry
  /// angular momentum across C's spin axis: then there is no steady spin to
  /// linearise about (theory §11.6), and this says why. SynthesizedStructure
  /// refuses such speeds.
  std::string steadySpinDefect(const std::vector<double>& speeds) const;
  /// A part spinning relative to a free C's frame (steadySpinDefect): its
  /// speed parameter, its angular momentum per unit rate J a, and the rate
  /// of the frame it turns with, as (speed parameter, coefficient) terms.
  struct RelativeMomentum {
    int speedParameter = -1;
    fem::Vec3 perUnitRate{0, 0, 0};
    std::vector<std::pair<int, double>> frame;
    fem::Vec3 frameAxis{0, 0, 1};  ///< the axis the frame's rate turns it about
  };
  Teuchos::RCP<const Teuchos::Comm<int>> comm() const { return comm_; }
  /// Names and physical DOF counts, tree order.
  std::vector<std::pair<std::string, long long>> substructureDofs() const;
  double assemblySeconds() const { return seconds_; }
  /// Approximations made, one line each (naming the substructure): report
  /// them with every result.
  const std::vector<std::string>& notes() const { return notes_; }

private:
  std::vector<std::shared_ptr<Part>> parts_;  ///< pre-order: parents before children
  std::vector<SpeedParameter> speeds_;
  bool free_ = false;
  std::vector<RelativeMomentum> relativeMomenta_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  double seconds_ = 0.0;
  std::vector<std::string> notes_;
};

/// One "Reduction" list per substructure, all with the same basis kind and
/// vector count, capped at each substructure's free DOFs (for strategy
/// comparisons). For "Partitioned", whose size follows a cut-off, `vectors`
/// is that cut-off in Hz (theory §18).
std::vector<Teuchos::ParameterList> sameReduction(const AssembledStructure& structure, const std::string& basis,
                                                  int vectors);

/// Per substructure: what its basis is and what it costs.
struct SubstructureReduction {
  std::string name, kind;   ///< kind: "C", "R", "E", "A"
  std::string basis;        ///< "Admissible", ..., "Full", "rigid" (R)
  long long physicalDofs = 0;
  int coordinates = 0;      ///< columns of q it owns
  int attachmentDofs = 0;   ///< held DOFs (its attachment or reference)
  std::vector<std::string> labels, dropped;
  std::string eigensolverReport;
  double seconds = 0.0;     ///< basis construction
  /// Its basis factored no K of its own: it adopted the prestress solve's
  /// factorisation of the same held stiffness (theory §11.4).
  bool adoptedPrestressFactor = false;
  /// Its error estimates' flexibility (K with its attachment held, theory
  /// §11.8) is that same prestress factorisation: the estimates factor
  /// nothing for it. Also for a basis that held other rows (a
  /// Craig-Bampton substructure with point-attached children: their
  /// interface rows).
  bool estimatesAdoptedPrestressFactor = false;
  /// A turned copy whose reduced matrices B^T A B are its prototype's by a
  /// congruence D^T (B_p^T A_p B_p) D (theory §15.2): no product with its
  /// matrices was taken for them.
  bool projectedFromPrototype = false;
  double basisBytes = 0.0;  ///< its vectors' storage (rows x columns x 8; 0 for Full and R)
  /// Rayleigh-Ritz estimates of its lowest frequencies at rest, attachment
  /// held (rad/s): the paper's truncation guide. Empty for Full and R.
  std::vector<double> frequencyEstimates;
  /// A copy of a "Copies: N" item: the prototype whose basis it turned
  /// instead of reducing again (no factorisation, no eigensolve; `seconds`
  /// is the turn and its check: theory §15.2). Empty otherwise.
  std::string turnedFrom;
  /// A copy reduced on its own because its matrices are not its
  /// prototype's turned, and why (a finding to report). Empty otherwise.
  std::string notTurned;
};

/// Whether a substructure's basis can represent its own modes below a
/// cut-off (doc/theory.md §11.9): the Sturm count of K - w_c^2 M with its
/// attachment held against the number of its Rayleigh-Ritz estimates below
/// w_c (a Ritz value is above its mode, so fewer means modes the basis lacks).
struct SubstructureCoverage {
  std::string name, basis;
  double cutoff = 0.0;        ///< rad/s
  long long sturmCount = -1;  ///< its modes below the cut-off, attachment held (-1: not counted)
  int represented = 0;        ///< its Ritz estimates below the cut-off
  int withinBand = 0;         ///< its Ritz estimates above the cut-off, within the band, taken as the missing count's modes
  int coordinates = 0;
  std::string verdict;        ///< "complete", "can miss N modes below X Hz", "Full", "rigid", or why not counted
};

/// What a reduced mode's accuracy is known to be without the truth
/// (doc/theory.md §11.8): an estimate always, a rigorous bound where the
/// structure is symmetric positive definite (SynthesizedStructure::boundsUnavailable).
struct ModeAccuracy {
  /// Estimated relative frequency error |omega - omega_truth| / omega; -1 for a
  /// zero frequency (rigid or critical): no estimate.
  double estimate = -1.0;
  /// Rigorous: a truth frequency lies within bound * omega of omega (Kato-Temple:
  /// the truth frequency just below omega; Krylov-Bogoliubov: some truth
  /// frequency). -1: no bound (not SPD, or a zero frequency).
  double bound = -1.0;
  std::string boundKind;   ///< "Kato-Temple", "Krylov-Bogoliubov", or empty
  double gapFactor = 0.0;  ///< b / (b - theta) of the Kato-Temple bound (0: not used)
  /// eps^2 = sum_s f_s^H K_a,s^-1 f_s for q^H M q = 1: the residual's squared
  /// K^-1 norm (the truth's exactly when bounds apply), rad^2/s^2.
  double residualSquared = 0.0;
};

/// The modes of the synthesised structure at one set of speeds.
struct StructureModes {
  eigen::GyroscopicResult result;
  std::string path;  ///< "dense" or "sparse", and why
  std::vector<double> speeds;
  double seconds = 0.0;
};

/// A mode's content in the cyclic harmonics of the copies of one "Copies: N"
/// item (doc/theory.md §15.3): the copies' motions u_j, turned back into the
/// prototype's axes, transformed over the copy index j,
/// c_h = sum_j u_j exp(-2 pi i j h / N), and the kinetic energy
/// c_h^H M c_h / N of each harmonic (Parseval: they sum to the copies').
struct CyclicContent {
  std::string group;  ///< the item as written ("blade")
  int copies = 0;     ///< N
  /// share[h], h = 0 .. N/2 (h and N - h together): of the copies' kinetic
  /// energy; sums to 1 (all zero when the copies do not move).
  std::vector<double> share;
  int dominant = 0;  ///< the h with the largest share
  /// "collective" (h = 0), "cyclic h" (the h-th cosine/sine pair: in phase
  /// with h nodal diameters), "differential" (h = N/2, N even: reactionless).
  std::string label() const;
};

/// What a mode is made of (doc/theory.md §11.6).
struct ModeCharacter {
  /// Per "Copies: N" item, its harmonic content (empty without copies).
  std::vector<CyclicContent> cyclic;
  /// Share of the mode's kinetic energy (u_s^H M_s u_s) in each
  /// substructure, tree order; sums to 1.
  std::vector<double> kineticShare;
  /// How much the mode deforms each substructure, relative to that
  /// substructure's own stiffness scale: u_s^H K_s u_s / (||K_s||_F u_s^H u_s),
  /// K_s its elastic stiffness (0 for a rigid rotor and for no motion). A
  /// rigid motion of the substructure gives rounding only (<< sqrt(eps));
  /// a vibration gives (omega / omega_max,s)^2-ish. Tells an unrestrained
  /// substructure from an ill-conditioned or critical-speed zero frequency
  /// (doc/theory.md §4.3).
  std::vector<double> relativeStrain;
  /// Share of q^H M q in the free C's six rigid-body coordinates (0 when C
  /// is clamped).
  double rigidShare = 0.0;
  /// A rigid motion of the free structure that is fixed in inertial space,
  /// seen from the spinning frame at the frame rate (rigidShare > 0.99 and
  /// omega = C's spin rate to 1e-4, the accuracy of a defective double
  /// eigenvalue): a kinematic artefact, not a vibration.
  bool frameArtefact = false;
};

/// How the substructures' bases are computed on several ranks (one rank:
/// the same thing). Substructures are independent until synthesis.
enum class ReductionSchedule {
  /// Each reduced substructure gathered whole onto one rank (largest first
  /// onto the least-loaded rank) and reduced there while the other ranks
  /// reduce theirs; only the bases come back. Full bases stay distributed.
  Concurrent,
  /// One substructure after another, each distributed over every rank.
  Distributed
};

/// A rotor spinning in its own frame on an attachment that moves (theory
/// §16.8). Its attachment motion enters the structure's coordinates as six
/// coordinates b of its own (rotor axes): the synthesised M, G, K, D are
/// constant in q_e = [..., b, ...]; the physical structure ties
/// b = R6(psi)^T A q_e, A the parent's attachment motion (fixed axes) and
/// R6 = blkdiag(R, R), R the turn by the hub azimuth psi = omega t about
/// `axis`. analysis::PeriodicStructure builds the periodic system from these.
struct MovingHub {
  std::size_t part = 0;          ///< the rotor (tree order)
  long long offset = 0;          ///< its b: coordinates offset .. offset + 5 of q_e
  int speedParameter = -1;       ///< omega, its spin relative to the parent
  fem::Vec3 axis{0, 0, 1};       ///< unit spin axis
  /// A: row a (0..5: u_P, theta_P in the parent's, fixed, axes) as (coordinate, coefficient) of q_e.
  std::vector<std::vector<std::pair<long long, double>>> parentMotion;
};

class SynthesizedStructure {
public:
  /// Every substructure reduced by its own "Reduction" parameters
  /// (`truth`: every basis Full). Collective. The first synthesis of an
  /// assembled structure takes the prestress factorisations it kept (theory
  /// §11.4): its reductions adopt them, and every synthesis frees them, so a
  /// later synthesis factors again (the same numbers, to rounding). Not to
  /// be called on one AssembledStructure from two threads at once.
  static SynthesizedStructure synthesize(const AssembledStructure& structure, bool truth = false);
  /// One "Reduction" list per substructure (tree order, as parts()).
  /// With `previous` (a synthesis of the same assembled structure), the
  /// substructures whose "Reduction" list is unchanged keep its bases, and
  /// every substructure keeps its held-stiffness factorisations (error
  /// estimates, coverage counts): enrichment rebuilds only what it changed.
  static SynthesizedStructure synthesize(const AssembledStructure& structure,
                                         const std::vector<Teuchos::ParameterList>& reductions,
                                         ReductionSchedule schedule = ReductionSchedule::Concurrent,
                                         const SynthesizedStructure* previous = nullptr);

  long long size() const;  ///< n, the number of coordinates q
  /// The assembled structure it was synthesised from.
  const AssembledStructure& assembled() const { return *structure_; }
  const std::vector<SubstructureReduction>& reductions() const { return reports_; }
  const std::vector<SpeedParameter>& speeds() const { return structure_->speeds(); }
  double synthesisSeconds() const { return seconds_; }
  /// Wall time of the bases alone (step 1 of synthesize; part of synthesisSeconds).
  double basesSeconds() const { return basesSeconds_; }

  /// The distributed M, G(s), K(s) (row map: the coordinates' map), and
  /// the damping D (independent of speed; null when undamped).
  eigen::SparseGyroscopicSystem system(const std::vector<double>& speeds) const;
  /// D = sum_s T_s^T D_s T_s plus the modal damping of reduced substructures
  /// (theory §13.1); null when no substructure is damped.
  Teuchos::RCP<const CrsMatrix> damping() const { return D_; }
  /// The substructures whose Modal Damping Ratio this synthesis left out:
  /// those with a reduced basis of their own made Full here (the truth,
  /// synthesize(structure, true)), which has no modal coordinates for it
  /// (theory §13.1). Its modes are then those of a less damped structure:
  /// not a truth to compare the reduced model with.
  const std::vector<std::string>& modalDampingOmitted() const { return modalDampingOmitted_; }
  /// The same, gathered to every rank (n up to a few thousand): M, D and
  /// each speed's piece of G and K are gathered once (collective, on first
  /// use) and combined per call.
  eigen::GyroscopicSystem denseSystem(const std::vector<double>& speeds) const;

  /// "Solver": Auto (dense when n <= "Dense Limit", else sparse), Dense or
  /// Sparse; "Number of Modes"; "Dense Solver" and "Sparse Solver" sublists
  /// passed to eigen::DenseGyroscopicSolver / SparseGyroscopicSolver.
  static Teuchos::RCP<const Teuchos::ParameterList> validSolveParameters();
  StructureModes solve(const std::vector<double>& speeds, const Teuchos::ParameterList& params) const;
  /// solve() at every set of `speeds`, in order. On the dense path the
  /// solves run on `threads` threads of this rank (0: the cores left to
  /// this rank, coresPerRank(ranksOnNode): the hardware threads over the
  /// ranks sharing this node,
  /// at most the cores the rank is bound to), each on its
  /// own copy of the parameters: the same results as one solve() after
  /// another (each is the same computation on the same matrices).
  /// Collective.
  std::vector<StructureModes> solveMany(const std::vector<std::vector<double>>& speeds,
                                        const Teuchos::ParameterList& params, int threads = 0) const;

  /// u_s = T_s q for each substructure, tree order (a rigid rotor's rows are
  /// its a = (u_P, theta_P), and its spin angle if free), formed for a Full
  /// substructure and a rigid rotor; null for a reduced one, whose T_s =
  /// B_s C_s (attachment motion and basis columns B_s, their rows over q
  /// C_s) is kept factored: formed, its rows would hold every coordinate
  /// its attachment reaches (a blade on a 24-blade disk's Craig-Bampton hub:
  /// 168 a row, against B_s's 18), and expand() applies the factors.
  const std::vector<Teuchos::RCP<const CrsMatrix>>& transforms() const { return T_; }
  Teuchos::RCP<const Map> coordinateMap() const { return map_; }
  /// The rotors on moving attachments (theory §16.8); empty for a structure
  /// with constant coefficients. With any, solve() refuses: the modes come
  /// from analysis::PeriodicStructure.
  const std::vector<MovingHub>& movingHubs() const { return hubs_; }
  /// Per part (tree order), its first own coordinate in q; it owns
  /// reductions()[k].coordinates of them.
  const std::vector<long long>& coordinateOffsets() const { return offsets_; }

  /// Physical displacements of each substructure (u_s = T_s q, real and
  /// imaginary parts as two columns) of mode `m` of `modes`. Collective.
  std::vector<Teuchos::RCP<MultiVector>> expand(const StructureModes& modes, int m) const;
  /// Energy shares and artefact flags of every mode (collective).
  std::vector<ModeCharacter> characterise(const StructureModes& modes) const;
  /// Per mode, an estimate of its relative frequency error against the
  /// truth model of the same structure, without solving it: the residual of
  /// each reduced substructure's full equations of motion on its interior
  /// (attachment and interface rows held), r_s = (lambda^2 M_s + lambda G_s
  /// + K_s) u_s, corrected statically, d omega = -sum_s r_s^H K_b,s^-1 r_s /
  /// (2 omega q^H M q + Im q^H G q) (doc/theory.md §11.8). -1 for a zero
  /// frequency (rigid or critical). One factorisation per reduced
  /// substructure. Collective. `shares`, if given, gets per mode each
  /// substructure's share of that estimate: its term r_s^H K_b,s^-1 r_s
  /// over their sum (each term >= 0; 0 for a Full basis or a rigid part,
  /// and where the sum is 0): where a reduction should grow to lower that
  /// mode's error (TruncationStudy's stalls, enrichToAccuracy), from the
  /// same solves.
  std::vector<double> errorEstimates(const StructureModes& modes,
                                     std::vector<std::vector<double>>* shares = nullptr) const;
  /// The same estimates with, where boundsUnavailable(modes.speeds) is empty,
  /// a rigorous bound per mode: Kato-Temple in the K^-1 norm with the gap
  /// to the next distinct Ritz value's Krylov-Bogoliubov interval, else
  /// Krylov-Bogoliubov (doc/theory.md §11.8). Collective. `shares` as
  /// for errorEstimates.
  std::vector<ModeAccuracy> accuracy(const StructureModes& modes,
                                     std::vector<std::vector<double>>* shares = nullptr) const;
  /// Empty when the truth at these speeds is symmetric positive definite
  /// with a block-diagonal stiffness in the floating-frame coordinates (at
  /// rest, clamped, point attachments, no grounded child, no free spin
  /// angle), so that the estimates' eps^2 is the truth's K^-1 norm of the
  /// residual and the bounds hold; else the reason they do not. Collective.
  std::string boundsUnavailable(const std::vector<double>& speeds) const;
  /// Per substructure, at cut-off `omega` (rad/s): its modes below it with
  /// its attachment held (one sparse LDL^T inertia, never of the assembled
  /// structure) against those its basis represents. `band` (relative, >=
  /// 0): how far above omega a Ritz value still counts as representing a
  /// mode below it, the cut-off's own uncertainty (the highest mode's
  /// estimated error): a value there is the mode approximated from above,
  /// and "can miss" would be a false alarm (theory §11.9). Collective.
  std::vector<SubstructureCoverage> coverage(double omega, double band = 0.0) const;
  /// Frees the factored held stiffnesses kept for the error estimates (the
  /// reduction's own factors, theory §11.8), here and in every synthesis
  /// sharing them: a caller done with estimates releases them before the
  /// coverage counts, whose factorisation was the run's peak memory with
  /// them held. Estimates asked for afterwards factor again.
  void releaseFlexibilities();

private:
  using SparseRow = std::vector<std::pair<GlobalOrdinal, double>>;
  /// The flops of part k's flexibility factorisation (K_a held), live or
  /// recorded when released; 0 if it never had one. Collective-consistent.
  double flexibilityFlops(std::size_t k) const;
  struct Sums;            ///< the projected matrices as they accumulate (synthesize, step 4)
  struct Factorisations;  ///< per substructure, built once and shared by copies and later syntheses
  // synthesize, in the order it runs:
  void buildBases(const std::vector<Teuchos::ParameterList>& reductions, ReductionSchedule schedule,
                  const SynthesizedStructure* previous);
  std::vector<GlobalOrdinal> layoutCoordinates();
  std::vector<SparseRow> attachmentMotion(std::size_t k, bool& moves);
  /// Copy k's D with Q^T B_k = B_prototype D (its projections from the
  /// prototype's), or nullopt. Collective.
  std::optional<std::vector<double>> copyRotation(std::size_t k, const MultiVector& B, int na, bool rigidColumns) const;
  /// A copy's r^T K^-1 r per column of modes m0 .. m0 + bm from its
  /// prototype's Gram matrix W (residualFlexibilityNorms), and its
  /// attachment forces X^T r into *toParent. Collective.
  std::vector<double> copyResidualNorms(std::size_t k, const StructureModes& modes, int m0, int bm,
                                        const std::vector<double>& D, const std::vector<substructure::Matrix>& terms,
                                        double frame, const std::vector<double>& W, const std::vector<double>& XP,
                                        std::vector<double>* toParent) const;
  /// y = C_k q for modes m0 .. m0 + bm (nb x 2 bm, column-major, real and
  /// imaginary parts; on every rank). Collective.
  std::vector<double> factorCoordinates(std::size_t k, const StructureModes& modes, int m0, int bm) const;
  /// expand() for the parts not skipped (null for those). Collective.
  std::vector<Teuchos::RCP<MultiVector>> expandParts(const StructureModes& modes, int m,
                                                     const std::vector<bool>& skip) const;
  /// Rows `rows` of part k's T (formed or B C) on every rank. Collective.
  std::map<GlobalOrdinal, SparseRow> transformRows(std::size_t k, const std::set<GlobalOrdinal>& rows) const;
  void projectRigidRotor(std::size_t k, const std::vector<SparseRow>& A, GlobalOrdinal offset, Sums& sums);
  void projectSubstructure(std::size_t k, const std::vector<SparseRow>& A, bool moves, GlobalOrdinal offset,
                           Sums& sums);
  void finishMatrices(Sums& sums);
  // The residual of every mode in each substructure's full equations
  // (errorEstimates, accuracy): per mode sum_s f_s^H K_a,s^-1 f_s.
  // byPart: each substructure's term, per mode.
  std::vector<double> residualFlexibilityNorms(const StructureModes& modes,
                                               std::vector<std::vector<double>>* byPart = nullptr) const;
  const reduction::StaticCorrection& flexibility(std::size_t k) const;
  /// Whether K X = 0 for part k's rigid motion X about its attachment point:
  /// nothing of its own (supports, grounded springs) holds it (cached).
  bool carriedRigidly(std::size_t k) const;
  /// A copy whose basis was turned and whose K and M are its prototype's
  /// turned: the prototype's factorisations serve it (theory §15.2).
  bool sharesPrototypeFactorisations(std::size_t k) const;

  std::shared_ptr<const AssembledStructure> structure_;
  std::vector<MovingHub> hubs_;
  std::vector<long long> offsets_;
  struct DensePieces;  ///< M, D, G_i, K0, K_ij gathered (denseSystem)
  std::shared_ptr<DensePieces> dense_;
  std::vector<reduction::RitzBasis> bases_;  ///< per part (empty for a rigid rotor)
  std::vector<Teuchos::ParameterList> reductionLists_;
  std::shared_ptr<Factorisations> factorisations_;
  Teuchos::RCP<const Map> map_;
  std::vector<Teuchos::RCP<const CrsMatrix>> T_;  ///< per part: u_s = T_s q (formed; or null and:)
  std::vector<Teuchos::RCP<const MultiVector>> B_;  ///< per reduced part: T_s = B_s C_s
  std::vector<std::vector<std::vector<std::pair<GlobalOrdinal, double>>>> C_;  ///< C_s's rows over q
  /// Per turned copy projected from its prototype: D with Q^T B_c = B_p D
  /// (copyRotation; empty otherwise), for its error estimates.
  std::vector<std::vector<double>> rotations_;
  /// Per reduced part with a modal damping ratio, its D_eta (k x k,
  /// column-major; theory §13.1); empty elsewhere. The error estimates lift
  /// its force to the physical rows (§11.8).
  std::vector<std::vector<double>> modalDamping_;
  std::vector<std::string> modalDampingOmitted_;
  Teuchos::RCP<const CrsMatrix> M_, K0_;
  Teuchos::RCP<const CrsMatrix> D_;  ///< viscous damping (null: none)
  std::vector<Teuchos::RCP<const CrsMatrix>> G_;  ///< per speed parameter
  std::vector<Teuchos::RCP<const CrsMatrix>> N_;  ///< circulatory per speed parameter (null: none; theory §13.1)
  struct KTerm {
    int i, j;
    Teuchos::RCP<const CrsMatrix> K;
  };
  std::vector<KTerm> K2_;
  /// K0_ and K2_ hold no reduced part's products B^T K B, only entries
  /// assembled from elements (Full substructures, monolithically): their
  /// magnitudes then bound K's rounding (GyroscopicSystem::KMagnitude).
  bool kEntrywise_ = false;
  std::vector<SubstructureReduction> reports_;
  double seconds_ = 0.0, basesSeconds_ = 0.0;
};

}  // namespace cms::synthesis
