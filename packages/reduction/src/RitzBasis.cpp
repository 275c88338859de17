// Ritz bases of one substructure (doc/theory.md §11.3): the dispatcher, the
// in-order M-orthonormalisation that makes nested sets nested subspaces, and
// the substructure frequency estimates of the paper's truncation guide.
#include "cms/reduction/RitzBasis.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <sstream>

#include <Teuchos_LAPACK.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include "HeldStiffness.hpp"
#include "LoadPatterns.hpp"
#include "SymmetricEigen.hpp"
#include "cms/core/SparseProduct.hpp"
#include "cms/core/MatrixSum.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"
#include "cms/core/DistributedDirectSolver.hpp"
#include "cms/core/SparseInertia.hpp"
#include <TpetraExt_MatrixMatrix.hpp>
#include "cms/reduction/AdmissibleVectors.hpp"
#include "cms/reduction/CraigBamptonBasis.hpp"
#include "cms/reduction/FixedInterfaceModes.hpp"
#include "cms/reduction/PartitionedBasis.hpp"
#include "cms/reduction/StaticCorrection.hpp"

namespace cms::reduction {

int RitzBasis::size() const {
  return vectors.is_null() ? 0 : static_cast<int>(vectors->getNumVectors());
}

Teuchos::RCP<const Teuchos::ParameterList> validParameters() {
  static Teuchos::RCP<const Teuchos::ParameterList> valid = [] {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Reduction"));
    Teuchos::setStringToIntegralParameter<int>(
        "Basis", "Admissible",
        "Admissible, Polynomial, Modes, Craig-Bampton, Guyan, Partitioned or Full (doc/theory.md §11.3, §18)",
        Teuchos::tuple<std::string>("Admissible", "Polynomial", "Modes", "Craig-Bampton", "Guyan", "Partitioned", "Full"),
        pl.get());
    pl->set("Vectors", 6,
            "Admissible: static and Krylov vectors; Polynomial: polynomial functions; Modes, Craig-Bampton: eigenvectors (Craig-Bampton adds "
            "one constraint mode per interface DOF); ignored by Guyan and Full. A child held by supports of its own gets "
            "their static corrections beyond it (theory §11.2)");
    pl->set("Load Patterns", Teuchos::Array<std::string>(Teuchos::tuple<std::string>("interfaces", "uniform", "rotation", "centrifugal")),
            "Admissible: static load patterns: interfaces (unit forces and moments at the "
            "children's attachments, always first), uniform (mass-weighted x, y, z), rotation (inertia "
            "loads of unit angular accelerations about x, y, z through the supports), centrifugal (spin "
            "only), tip (unit x, y, z at the free node farthest from the supports); the others enter "
            "the Krylov sequence softest first (doc/theory.md §11.3)");
    pl->set("Cutoff Frequency", 0.0,
            "Hz; > 0: the vector count from the substructure's own modes below it, counted by a Sturm "
            "sequence (LDL^T inertia of K - w^2 M, held as the basis holds them), as Nastran's ACMS: "
            "Modes and Craig-Bampton take every fixed-interface mode below it; Admissible grows until "
            "its Rayleigh-Ritz estimates below it are as many (doc/theory.md §11.10); \"Vectors\" is "
            "then ignored. 0: use \"Vectors\"");
    {
      Teuchos::ParameterList& part = pl->sublist("Partition", false,
                                                 "Partitioned: how the substructure is cut (Scotch) into parts, "
                                                 "each reduced to its modes below \"Cutoff Frequency\" with the "
                                                 "separator held, the separator to its own modes below it "
                                                 "(doc/theory.md §18)");
      part.set("Parts", 0, "> 0: this many parts; 0: as many as \"Max DOFs\" asks");
      part.set("Max DOFs", 20000, "parts of at most about this many free DOFs (when \"Parts\" is 0)");
      part.set("Interface Cutoff Factor", 2.0,
               "the interface keeps its modes below this multiple of \"Cutoff Frequency\" (>= 1)");
      Teuchos::setStringToIntegralParameter<int>(
          "Interface", "Auto",
          "the interface problem's coordinates: Exact (every separator DOF: its exact Schur complement, as many "
          "solves per part as separator DOFs it touches, n_B^2 memory), Polynomial (per connected piece of the "
          "separator, children's attachment faces included, polynomials of degree <= \"Interface Degree\" in its "
          "coordinates: the problem projected on them, from above; the static shapes still exact; doc/theory.md "
          "§18.4), or Auto (Exact up to \"Exact Interface Limit\" separator DOFs, Polynomial beyond)",
          Teuchos::tuple<std::string>("Auto", "Exact", "Polynomial"), &part);
      part.set("Exact Interface Limit", 2000, "Interface Auto: the exact interface up to this many separator DOFs");
      part.set("Interface Degree", 3, "Polynomial interface: the highest degree of its polynomials (>= 0)");
      part.set("Static Solve Tolerance", 1e-12,
               "Polynomial interface: the static shapes' separator values are solved by block conjugate gradients on the "
               "Schur complement (never formed) to this relative residual");
      part.set("Static Solve Iterations", 500, "Polynomial interface: at most this many block conjugate-gradient iterations");
      part.set("Residual Vectors", true,
               "per interface mode, the parts' static response to its inertia load (one load-dependent "
               "Ritz step; measured: 20x smaller errors for 1.7x the vectors)");
    }
    pl->set("Dependence Tolerance", 1e-8,
            "A candidate whose M-norm after projection on the kept columns falls below this fraction of "
            "its norm is dropped as dependent (reported)");
    pl->set("Eigensolver Tolerance", 1e-10, "Modes, Craig-Bampton: Anasazi convergence tolerance");
    Teuchos::setStringToIntegralParameter<int>(
        "Direct Solver", "Auto",
        "Who factors the stiffness with the attachment held (and the cut-off's Sturm count): CHOLMOD, "
        "gathered to one rank; MUMPS, across the ranks the substructure is distributed over; Auto: MUMPS "
        "when it is distributed over more than one rank (ReductionSchedule::Distributed) and K has at "
        "least 3e7 stored entries (below that the gathered CHOLMOD measured faster), else CHOLMOD",
        Teuchos::tuple<std::string>("Auto", "CHOLMOD", "MUMPS"), pl.get());
    return pl;
  }();
  return valid;
}

void appendOrthonormal(const CrsMatrix& M, const MultiVector& candidates, const std::vector<std::string>& labels,
                       double tolerance, int maxColumns, RitzBasis& basis) {
  const auto map = candidates.getMap();
  std::vector<Teuchos::RCP<Vector>> kept, Mkept;
  if (!basis.vectors.is_null()) {
    for (std::size_t j = 0; j < basis.vectors->getNumVectors(); ++j) {
      kept.push_back(Teuchos::rcp(new Vector(*basis.vectors->getVector(j), Teuchos::Copy)));
      Mkept.push_back(Teuchos::rcp(new Vector(map)));
      M.apply(*kept.back(), *Mkept.back());
    }
  }
  const std::size_t before = kept.size();
  Vector c(map), Mc(map);
  for (std::size_t j = 0; j < candidates.getNumVectors() && static_cast<int>(kept.size()) < maxColumns; ++j) {
    c.assign(*candidates.getVector(j));
    multiply(M, c, Mc);
    const double norm0 = std::sqrt(std::max(0.0, c.dot(Mc)));
    if (!(norm0 > 0.0)) {
      basis.dropped.push_back(labels[j] + " (zero M-norm: the pattern has no mass on free DOFs)");
      continue;
    }
    // Classical Gram-Schmidt twice ("twice is enough", Giraud et al. 2005):
    // orthogonal to working precision whatever the conditioning.
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t k = 0; k < kept.size(); ++k) c.update(-Mkept[k]->dot(c), *kept[k], 1.0);
    }
    multiply(M, c, Mc);
    const double norm = std::sqrt(std::max(0.0, c.dot(Mc)));
    if (!(norm > tolerance * norm0)) {
      std::ostringstream os;
      os << labels[j] << " (relative norm " << norm / norm0 << " after projection, tolerance " << tolerance << ")";
      basis.dropped.push_back(os.str());
      continue;
    }
    c.scale(1.0 / norm);
    Mc.scale(1.0 / norm);
    kept.push_back(Teuchos::rcp(new Vector(c, Teuchos::Copy)));
    Mkept.push_back(Teuchos::rcp(new Vector(Mc, Teuchos::Copy)));
    basis.labels.push_back(labels[j]);
  }
  if (kept.size() == before) return;
  auto V = Teuchos::rcp(new MultiVector(map, kept.size()));
  for (std::size_t k = 0; k < kept.size(); ++k) V->getVectorNonConst(k)->assign(*kept[k]);
  basis.vectors = V;
  // Projections of the columns before are not those of these.
  basis.projectedK.clear(), basis.projectedM.clear();
}

bool adoptsStiffnessFactor(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                           const Teuchos::ParameterList& params) {
  const auto& f = boundary.stiffnessFactor;
  if (!f) return false;
  Teuchos::ParameterList p(params);
  try {
    p.validateParametersAndSetDefaults(*validParameters());
  } catch (const std::exception&) {
    return false;  // buildRitzBasis refuses them, naming the key
  }
  const std::string kind = p.get<std::string>("Basis");
  std::vector<GlobalOrdinal> held;
  if (kind == "Admissible" || kind == "Modes") held = boundary.held;
  else if (kind == "Craig-Bampton" || kind == "Guyan") held = craigBamptonHeldRows(boundary);
  else return false;  // Full factors nothing; Polynomial and Partitioned factor other matrices
  // A cut-off's Sturm count would run while the factor is resident.
  return !(p.get<double>("Cutoff Frequency") > 0.0) &&
         detail::factorFits(*f, s, std::move(held), p.get<std::string>("Direct Solver"));
}

RitzBasis buildRitzBasis(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                         const Teuchos::ParameterList& params) {
  const auto t0 = std::chrono::steady_clock::now();
  Teuchos::ParameterList p(params);
  try {
    p.validateParametersAndSetDefaults(*validParameters());
  } catch (const std::exception& e) {
    throw InputError(s.name() + ": \"Reduction\": " + std::string(e.what()));
  }
  const std::string kind = p.get<std::string>("Basis");
  // Every held-stiffness factorisation below (detail::HeldStiffness) by this choice.
  const detail::DirectSolverScope directSolver(p.get<std::string>("Direct Solver"));
  const detail::OfferedFactorScope offered(boundary.stiffnessFactor);
  int vectors = p.get<int>("Vectors");
  CMS_INPUT_CHECK(vectors < 0, s.name() << ": \"Reduction\" -> \"Vectors\" = " << vectors << " must be >= 0");
  // Both are fractions: a negative one was taken as given (no candidate ever
  // dropped as dependent; an eigensolver told to converge below zero).
  for (const char* key : {"Dependence Tolerance", "Eigensolver Tolerance"}) {
    const double t = p.get<double>(key);
    CMS_INPUT_CHECK(!(t > 0.0 && t < 1.0),
                    "Scene/Substructures/" << s.name() << "/Reduction/" << key << " = " << t << " must be in (0, 1)");
  }
  const long long freeRows = s.dofs().rows() - static_cast<long long>(boundary.held.size());
  const double cutoffHz = p.get<double>("Cutoff Frequency");
  CMS_INPUT_CHECK(!(cutoffHz >= 0.0) || !std::isfinite(cutoffHz),
                  "Scene/Substructures/" << s.name() << "/Reduction/Cutoff Frequency = " << cutoffHz
                                         << " must be finite and >= 0 (Hz)");
  int below = -1;  // the substructure's own modes below the cut-off (held as the basis holds them)
  int freedConstraints = 0;  // distributing interfaces' constraints the count leaves free
  int represented = -1;      // an Admissible basis's Rayleigh-Ritz values below the cut-off
  SturmCut sturmCut;         // the count, for the modes of Modes and Craig-Bampton
  // (Partitioned applies the cut-off per part and to the interface: no
  // count over the whole substructure, whose factorisation it avoids.)
  if (cutoffHz > 0.0 && kind != "Full" && kind != "Guyan" && kind != "Partitioned") {
    std::vector<GlobalOrdinal> held(boundary.held);
    if (kind == "Craig-Bampton") {
      // Fixed-interface modes: the point interfaces held too, and a
      // distributing interface constrained by H u = 0 (its 6 fitted
      // coordinates), not held row by row. Holding its rows counted a more
      // constrained problem with fewer modes below the cut-off, and the
      // basis took too few (found by a review). Its rows are left free in
      // the count: H u = 0 removes m directions, so the constrained problem
      // has between count - m and count modes below (interlacing), never
      // more; the basis takes `count`, at most m more than needed.
      held = craigBamptonHeldRows(boundary);
      // m: the independent constraints (two children fitted to one face
      // constrain it once; counted 12 for 6, the basis took 6 modes short).
      bool anyDistributing = false;
      for (std::size_t c = 0; c < boundary.interfaces.size() && c < boundary.interfaceLoads.size(); ++c)
        anyDistributing = anyDistributing || boundary.interfaceLoads[c].size() < boundary.interfaces[c].size();
      if (anyDistributing) {
        std::vector<std::string> unused;
        freedConstraints = static_cast<int>(distributingConstraints(s, boundary, held, unused)->getNumVectors());
      }
    }
    const double w = 2.0 * M_PI * cutoffHz;
    Teuchos::RCP<const CrsMatrix> A =
        matrixSum(1.0, *holdDofsScaled(*s.K(), held), -w * w, *holdDofs(*s.M(), held, 0.0));
    // Handed over to the count: freed once it holds the values (MUMPS's triplets).
    const bool distributed =
        useDistributedSolver(detail::DirectSolverScope::current(), *A, kDistributedAutoEntriesReduction);
    const auto count = distributed ? distributedInertia(std::move(A)) : inertia(std::move(A));
    if (!count.reliable())
      throw NumericalError(s.name() + ": the Sturm count at the cut-off " + std::to_string(cutoffHz) +
                           " Hz failed (" + (count.failure.empty() ? "a pivot zero to rounding: the cut-off is one "
                                                                     "of its frequencies; move it" : count.failure) + ")");
    below = static_cast<int>(count.negative);
    vectors = below;
    // The constrained problem has only rows - held - m modes in all, and
    // with the m constraints left free the count can exceed that: a
    // cut-off above them all takes them all (it was refused, blaming a
    // "Vectors" the scene never gave; found by a review).
    if (freedConstraints > 0) {
      const std::set<GlobalOrdinal> rowsHeld(held.begin(), held.end());
      const long long nfree = s.dofs().rows() - static_cast<long long>(rowsHeld.size()) - freedConstraints;
      vectors = static_cast<int>(std::min<long long>(below, std::max<long long>(nfree, 0)));
    }
    // What the modes found are checked against (FixedInterfaceModes.hpp):
    // a distributing interface's constraints may take up to m of them.
    sturmCut = {w * w, below - freedConstraints};
  }
  RitzBasis basis;
  if (kind == "Full") {
    basis.kind = kind;
    basis.full = true;
  } else if (kind == "Admissible") {
    CMS_INPUT_CHECK(vectors > freeRows, "Scene/Substructures/" << s.name() << "/Reduction/Vectors = " << vectors
                                                 << " but substructure \"" << s.name() << "\" has only " << freeRows
                                                 << " free DOFs");
    const auto patterns = p.get<Teuchos::Array<std::string>>("Load Patterns");
    const std::vector<std::string> loads(patterns.begin(), patterns.end());
    if (below < 0) {
      basis = admissibleVectors(s, boundary, loads, vectors, p.get<double>("Dependence Tolerance"));
    } else {
      // Grow until the Rayleigh-Ritz estimates below the cut-off are as many
      // as its modes there (nested: a larger count keeps the smaller span).
      const double w = 2.0 * M_PI * cutoffHz;
      for (int k = std::max(1, below);; k = std::min<long long>(freeRows, k + std::max(2, k / 4))) {
        basis = admissibleVectors(s, boundary, loads, k, p.get<double>("Dependence Tolerance"));
        const auto est = estimateFrequencies(s, basis);
        represented = static_cast<int>(std::count_if(est.begin(), est.end(), [&](double x) { return x < w; }));
        if (represented >= below || k >= freeRows || basis.size() < k) break;
      }
    }
  } else if (kind == "Partitioned") {
    const auto& part = p.sublist("Partition");
    PartitionOptions options;
    options.parts = part.get<int>("Parts");
    options.maxDofs = part.get<int>("Max DOFs");
    options.interfaceCutoffFactor = part.get<double>("Interface Cutoff Factor");
    options.residualVectors = part.get<bool>("Residual Vectors");
    const std::string interface = part.get<std::string>("Interface");
    options.interface = interface == "Exact"        ? PartitionOptions::Interface::Exact
                        : interface == "Polynomial" ? PartitionOptions::Interface::Polynomial
                                                    : PartitionOptions::Interface::Auto;
    options.exactInterfaceLimit = part.get<int>("Exact Interface Limit");
    options.interfaceDegree = part.get<int>("Interface Degree");
    options.staticTolerance = part.get<double>("Static Solve Tolerance");
    options.staticIterations = part.get<int>("Static Solve Iterations");
    const auto patterns = p.get<Teuchos::Array<std::string>>("Load Patterns");
    options.loadPatterns.assign(patterns.begin(), patterns.end());
    options.cutoffHz = cutoffHz;
    options.eigensolverTolerance = p.get<double>("Eigensolver Tolerance");
    options.dependenceTolerance = p.get<double>("Dependence Tolerance");
    basis = partitionedBasis(s, boundary, options);
  } else if (kind == "Polynomial") {
    CMS_INPUT_CHECK(vectors > freeRows, "Scene/Substructures/" << s.name() << "/Reduction/Vectors = " << vectors
                                                 << " but substructure \"" << s.name() << "\" has only " << freeRows
                                                 << " free DOFs");
    basis = polynomialVectors(s, boundary, vectors, p.get<double>("Dependence Tolerance"));
  } else if (kind == "Modes") {
    CMS_INPUT_CHECK(vectors > freeRows, "Scene/Substructures/" << s.name() << "/Reduction/Vectors = " << vectors
                                                 << " but substructure \"" << s.name() << "\" has only " << freeRows
                                                 << " free DOFs");
    basis = fixedInterfaceModes(s, boundary.held, vectors, p.get<double>("Eigensolver Tolerance"),
                                p.get<double>("Dependence Tolerance"), {}, sturmCut);
  } else {
    const int modes = kind == "Guyan" ? 0 : vectors;
    basis = craigBamptonBasis(s, boundary, modes, p.get<double>("Eigensolver Tolerance"),
                              p.get<double>("Dependence Tolerance"), sturmCut);
  }
  // A child held by supports or springs of its own: the static correction
  // K_h^-1 K X of its attachment's rigid motion X (theory §11.2), without
  // which X is no constraint mode (Craig-Bampton 8 of a propped boom was 59%
  // off). Admissible and Partitioned have it among their load patterns'
  // static shapes; the others add it after their own columns, beyond
  // "Vectors" as Craig-Bampton's constraint modes are (nested still: the
  // same columns after each count's). K_h is the estimates' flexibility too.
  if (boundary.supportedAttachment &&
      (kind == "Modes" || kind == "Craig-Bampton" || kind == "Guyan" || kind == "Polynomial")) {
    Teuchos::RCP<MultiVector> R;
    std::vector<std::string> labels;
    detail::ownSupportLoads(s, boundary, R, labels);
    if (!R.is_null()) {
      auto K = std::make_unique<detail::HeldStiffness>(s, boundary.held);  // the offered factor, where it fits
      MultiVector Y(R->getMap(), R->getNumVectors());
      K->solve(*R, Y);
      appendOrthonormal(*s.M(), Y, labels, p.get<double>("Dependence Tolerance"),
                        basis.size() + static_cast<int>(R->getNumVectors()), basis);
      if (!basis.flexibility) basis.flexibility = std::make_shared<const StaticCorrection>(std::move(K));
    }
  }
  basis.kind = kind;
  basis.adoptedFactor = offered.adopted();
  if (below >= 0) {
    std::ostringstream os;
    os << "cut-off " << cutoffHz << " Hz: " << below << " of its modes below it (Sturm count";
    if (freedConstraints > 0)
      os << " with its distributing interfaces free: up to " << freedConstraints << " fewer under their constraints";
    os << "), " << basis.size() << " vectors";
    // The load patterns' Krylov sequence can end before it reaches every
    // mode below the cut-off (forces that never twist a beam): said, not
    // hidden behind the count (found by a review).
    if (represented >= 0 && represented < below)
      os << "; FINDING: only " << represented << " represented (the load patterns' Krylov sequence ended at "
         << basis.size() << " vectors: add load patterns, or use Modes or Craig-Bampton)";
    basis.eigensolverReport += (basis.eigensolverReport.empty() ? "" : "; ") + os.str();
  }
  basis.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return basis;
}

std::vector<double> estimateFrequencies(const substructure::Substructure& s, const RitzBasis& basis) {
  if (basis.vectors.is_null()) return {};
  const MultiVector& V = *basis.vectors;
  const int k = static_cast<int>(V.getNumVectors());
  // Small dense projections, replicated: the construction's own, or column
  // dot products.
  std::vector<double> Kr = basis.projectedK, Mr = basis.projectedM;
  if (Kr.size() != static_cast<std::size_t>(k) * k || Mr.size() != Kr.size()) {
    MultiVector KV(V.getMap(), k), MV(V.getMap(), k);
    multiply(*s.K(), V, KV);
    multiply(*s.M(), V, MV);
    Kr.assign(static_cast<std::size_t>(k) * k, 0.0), Mr.assign(static_cast<std::size_t>(k) * k, 0.0);
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        Kr[i + j * k] = V.getVector(i)->dot(*KV.getVector(j));
        Mr[i + j * k] = V.getVector(i)->dot(*MV.getVector(j));
      }
  }
  std::vector<double> w;
  const int info = detail::symmetricEigen(Kr, Mr, k, false, w);
  if (info != 0) throw NumericalError(s.name() + ": Rayleigh-Ritz estimate failed (LAPACK dsygv info " +
                                      std::to_string(info) + ")");
  std::vector<double> omega(k);
  for (int i = 0; i < k; ++i) omega[i] = std::sqrt(std::max(0.0, w[i]));
  return omega;
}

}  // namespace cms::reduction
