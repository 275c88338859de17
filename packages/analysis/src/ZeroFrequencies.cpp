#include "cms/analysis/ZeroFrequencies.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/SparseInertia.hpp"
#include "cms/core/TpetraTypes.hpp"
#include "cms/eigen/SturmCount.hpp"
#include "cms/fem/FiniteElementModel.hpp"
#include "cms/fem/MatrixSubstructureFile.hpp"

namespace cms::analysis {
namespace {

using synthesis::ModeCharacter;
using synthesis::StructureModes;

std::vector<int> zeroModes(const StructureModes& modes) {
  std::vector<int> z;
  for (std::size_t m = 0; m < modes.result.modes.size(); ++m)
    if (modes.result.modes[m].stability == eigen::Stability::RigidBody) z.push_back(static_cast<int>(m));
  return z;
}

// A rigid motion of a substructure strains it by rounding only: u^H K u /
// (||K|| u^H u) is then of order eps (the error of u in directions K sees).
// A vibration strains it by (omega / omega_max)^2 of that substructure,
// which for a mode that rounding cannot tell from zero in the coupled K is
// still far above eps unless the substructure itself is that ill-conditioned.
// sqrt(eps) splits the two with eight decades on either side.
const double kStrainSplit = std::sqrt(std::numeric_limits<double>::epsilon());

std::size_t argmax(const std::vector<double>& v) {
  return static_cast<std::size_t>(std::max_element(v.begin(), v.end()) - v.begin());
}

// The substructure a mode strains most, among those that take part in it.
// relativeStrain divides by each substructure's own motion, so one whose
// kinetic share is rounding (below eps: a motion below ~sqrt(eps) of the
// mode's) reads its own conditioning, not the mode's: a clamped hub under a
// solid child free to turn about a line of nodes read 7.4e-5 at a share of
// 3e-24, and the child's rigid turn was called "ill-conditioned" (found by
// a review). Substructure 0 where none takes part.
std::size_t mostStrained(const ModeCharacter& c) {
  const double eps = std::numeric_limits<double>::epsilon();
  std::size_t at = 0;
  double worst = -1.0;
  for (std::size_t s = 0; s < c.relativeStrain.size(); ++s)
    if (c.kineticShare[s] > eps && c.relativeStrain[s] > worst) worst = c.relativeStrain[s], at = s;
  return at;
}
double modeStrain(const ModeCharacter& c) {
  return c.relativeStrain.empty() ? 0.0 : c.relativeStrain[mostStrained(c)];
}

// ||K||_F / ||M||_F of substructure k: its stiffness scale in (rad/s)^2.
double stiffnessScale(const synthesis::AssembledStructure& s, std::size_t k) {
  const auto* sub = s.assembled(k);
  if (!sub) return 0.0;
  const double m = sub->frobeniusNorm(substructure::Matrix::M);
  return m > 0.0 ? sub->frobeniusNorm(substructure::Matrix::K) / m : 0.0;
}

// "ux 0.50, uy 0.50": the components that carry more than 5% of a
// substructure's motion in one mode (u_s from expand: real and imaginary
// columns). Collective.
std::string freeMotion(const synthesis::AssembledStructure& s, std::size_t k, const MultiVector& u) {
  std::array<double, 6> local{}, global{};
  const auto* sub = s.assembled(k);
  const auto map = u.getMap();
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
    const auto g = map->getGlobalElement(static_cast<LocalOrdinal>(l));
    int c = static_cast<int>(g % 6);  // a rigid rotor's rows: a = (u_P, theta_P)
    if (sub) c = static_cast<int>(sub->dofs().components.at(static_cast<std::size_t>(g)));
    if (c < 6) local[c] += std::pow(u.getData(0)[l], 2) + std::pow(u.getData(1)[l], 2);
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, 6, local.data(), global.data());
  double total = 0.0;
  for (double v : global) total += v;
  std::ostringstream os;
  os.precision(2);
  for (int c = 0; c < 6; ++c)
    if (total > 0.0 && global[c] > 0.05 * total)
      os << (os.tellp() > 0 ? ", " : "") << fem::componentName(static_cast<fem::Component>(c)) << ' '
         << global[c] / total;
  return os.str();
}

/// Whether substructure k's mesh holds reduced-integration Hex20 cells.
bool hasReducedHex20(const synthesis::AssembledStructure& structure, std::size_t k) {
  const auto& model = structure.substructure(k).model;
  if (!model || !model->mesh) return false;
  for (const auto& set : model->elementSets) {
    if (set.kind != fem::ElementSet::Kind::Solid || !model->mesh->hasGroup(set.group)) continue;
    for (const auto& b : model->mesh->group(set.group).blocks)
      if (b.type == mesh::CellType::Hex20 && fem::solidTypeOf(set, b) == fem::SolidType::Hex20Reduced) return true;
  }
  return false;
}

}  // namespace

/// Negative eigenvalues of a dense symmetric K by its Bunch-Kaufman L D L^T
/// (eigen::symmetricNegatives, read as the Sturm count reads its factor), K first scaled
/// symmetrically by its diagonal's magnitudes (S K S, S = |diag K|^-1/2
/// where the diagonal is not zero; the inertia is unchanged) so that a
/// pivot's "zero to rounding", 1e-13, is relative to its own row's
/// stiffness: against the largest diagonal a soft spring on a chain 1e12
/// times stiffer went negative 5% late, and at 1e16 never (a review).
/// With the magnitudes of K's parts R (GyroscopicSystem::KMagnitude), by
/// R's diagonal instead: at a critical speed K's own diagonal can be the
/// cancelled value (a point mass at Omega = sqrt(kx / m), kx - m Omega^2 =
/// -4.4e-16 of 2), which scaling by itself turns into a pivot of -1.
StiffnessCount denseStiffnessCount(const DenseMatrix& K, const DenseMatrix* R) {
  StiffnessCount out;
  const int n = K.numRows();
  out.negative = 0;
  if (n == 0) return out;
  const bool parts = R && R->numRows() == n;
  out.againstParts = parts;
  std::vector<double> sc(n, 1.0);
  for (int i = 0; i < n; ++i) {
    const double d = parts ? (*R)(i, i) : std::abs(K(i, i));
    if (d > 0.0) sc[i] = 1.0 / std::sqrt(d);
  }
  std::vector<double> A(static_cast<std::size_t>(n) * n);  // lower triangle read
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i) A[static_cast<std::size_t>(j) * n + i] = sc[i] * K(i, j) * sc[j];
  try {
    int within = 0;
    out.negative = eigen::symmetricNegatives(A, n, /*tiny*/ 1e-13, &within);
    out.tinyPivots = within;
  } catch (const NumericalError& e) {
    out.negative = -1;
    out.why = e.what();
  }
  return out;
}

StiffnessCount stiffnessCount(const synthesis::SynthesizedStructure& reduced, const std::vector<double>& speeds,
                              int denseLimit) {
  StiffnessCount out;
  if (reduced.size() <= denseLimit) {
    const auto sys = reduced.denseSystem(speeds);
    out = denseStiffnessCount(sys.K, &sys.KMagnitude);
    out.circulatory = sys.N.numRows() > 0;
    return out;
  }
  // The sparse inertia, K scaled by its diagonal's magnitudes first, as the
  // dense count is (its zero-pivot test is against the largest diagonal).
  const auto sys = reduced.system(speeds);
  out.circulatory = !sys.N.is_null();
  auto K = Teuchos::rcp(new CrsMatrix(*sys.K, Teuchos::Copy));
  Vector d(K->getRowMap());
  K->getLocalDiagCopy(d);
  {
    auto v = d.getLocalViewHost(Tpetra::Access::ReadWrite);
    for (std::size_t i = 0; i < d.getLocalLength(); ++i) v(i, 0) = std::abs(v(i, 0)) > 0.0 ? 1.0 / std::sqrt(std::abs(v(i, 0))) : 1.0;
  }
  K->leftScale(d);
  K->rightScale(d);
  const auto count = inertia(Teuchos::RCP<const CrsMatrix>(K));
  if (!count.failure.empty()) {
    out.why = "the sparse inertia failed: " + count.failure;
    return out;
  }
  // Without pivoting a pivot zero to rounding may be a leading minor's,
  // not K's: the count there is not trusted (no speed read from it).
  if (count.tinyPivots > 0) {
    out.why = "the sparse inertia met " + std::to_string(count.tinyPivots) + " pivot(s) zero to rounding";
    return out;
  }
  out.negative = count.negative;
  return out;
}

int rigidBodyMotions(const synthesis::AssembledStructure& structure) {
  int expected = structure.freeFloating() ? 6 : 0;
  for (std::size_t k = 0; k < structure.numSubstructures(); ++k)
    expected += structure.substructure(k).kind == synthesis::SubstructureKind::Rigid &&
                structure.substructure(k).rotor.spinCoordinate;
  return expected;
}

ZeroFrequencyReport checkZeroFrequencies(const synthesis::AssembledStructure& structure,
                                         const synthesis::SynthesizedStructure& reduced, StructureModes& modes,
                                         const Teuchos::ParameterList& solveParams) {
  ZeroFrequencyReport report;
  report.expected = rigidBodyMotions(structure);
  const auto zeros = zeroModes(modes);
  report.zeros = static_cast<int>(zeros.size());
  const bool spinning =
      std::any_of(modes.speeds.begin(), modes.speeds.end(), [](double w) { return w != 0.0; });
  // In a structure holding reduced Hex20 cells, an unstable mode at speed
  // may be the spin's softening of their zero-energy modes (a C3D20R column
  // one element across diverged, exit 0; found by a review): the at-rest
  // check below is then made too, and refuses the structure as it does at
  // rest. Not elsewhere: a free hinge is a zero at rest too, and a shaft
  // carrying one, unstable between its critical speeds for its own reasons,
  // was refused when every structure was (found by a review).
  bool reducedHex20 = false;
  for (std::size_t k = 0; k < structure.numSubstructures(); ++k) reducedHex20 = reducedHex20 || hasReducedHex20(structure, k);
  const bool unstable = spinning && reducedHex20 && !modes.result.isStable();
  if (report.zeros <= report.expected && !unstable) {
    // At speed a free body's rigid motions need not stay at zero: in a
    // spinning frame four of its six move to the frame rate, and a spinning
    // wheel turns its tilts into nutation. A zero within the count of six
    // can then be a critical speed: a free shaft's bending mode at zero,
    // labelled rigid (found by a review). At speed every zero that strains
    // the structure is judged below, not only those beyond the count.
    if (!spinning || zeros.empty()) return report;
  }
  // Each zero's strain at the scene's speeds, formed once (a characterise
  // per mode; it was formed a second time for the relabelling below).
  std::vector<synthesis::ModeCharacter> atSpeed;
  const auto strained = [&](int m) {
    return modeStrain(atSpeed[m]) > kStrainSplit;
  };
  if (spinning) {
    atSpeed = reduced.characterise(modes);
    if (report.zeros <= report.expected && std::none_of(zeros.begin(), zeros.end(), strained) && !unstable)
      return report;
  }

  // 1. At a critical speed, K(Omega) is singular but K(0) is not: the zeros
  // beyond the rigid-body motions appear with the speed (theory §4.3).
  StructureModes rest;
  if (spinning) {
    rest = reduced.solve(std::vector<double>(modes.speeds.size(), 0.0), solveParams);
    if (static_cast<int>(zeroModes(rest).size()) <= report.expected) {
      // Relabelled: every zero that strains the structure (at speed a
      // rigid motion does not; the count of six is no bound there, above).
      int excess = report.zeros - report.expected;
      for (int m : zeros)
        if (strained(m)) {
          modes.result.modes[m].stability = eigen::Stability::Critical;
          ++report.critical, --excess;
        }
      for (auto it = zeros.rbegin(); excess > 0 && it != zeros.rend(); ++it)  // none strained: the last ones
        if (modes.result.modes[*it].stability == eigen::Stability::RigidBody) {
          modes.result.modes[*it].stability = eigen::Stability::Critical;
          ++report.critical, --excess;
        }
      // Inside a divergence band, not at its edge: where K(Omega) has an
      // odd number of negative eigenvalues, det K < 0, and det(lambda^2 M +
      // lambda (G + D) + K), positive for large real lambda (M > 0), has a
      // real root lambda > 0 (theory §12.1, "A band between two speeds").
      // An anisotropic shaft in its own frame, divergent from 78.29 to
      // 79.63 rad/s, printed its root "critical" with a growth of 0.37-0.67
      // 1/s, below the zero tests' reach on a scale of 7e7 rad/s (the stiff
      // support's), and the dense path never shows a real value nonzero
      // (theory §4.3). Restrained at rest only (checked above: a mechanism's
      // sign at speed can be its rounding's), no rigid motions (their K is
      // singular at every speed), no circulatory N; the count made against
      // the magnitudes of K's parts (every part Full), which refuses a pivot
      // zero to their rounding: at the band's edge, a critical speed, K's
      // own diagonal has cancelled (the point mass at Omega = sqrt(kx / m)
      // read DIVERGENCE from a count scaled by it). The zero with the
      // largest positive real part, real within its own first-order error,
      // is the root.
      if (report.expected == 0 && report.critical > 0) {
        const int limit = solveParams.isParameter("Dense Limit") ? solveParams.get<int>("Dense Limit") : 1500;
        const auto count = stiffnessCount(reduced, modes.speeds, limit);
        // A pivot zero to rounding (within 1e-13 of its scaled row) is
        // counted neither way: at the band's upper edge the count was odd
        // from the clearly negative pivots, and the edge's zero read
        // DIVERGENCE (a review). And the parity proves one real root more
        // only where the roots already printed DIVERGENCE are even in
        // number: a mass exactly at its critical speed beside another inside
        // its band read two (a review).
        int shown = 0;
        for (const auto& mode : modes.result.modes)
          shown += mode.stability == eigen::Stability::Divergence;
        if (count.againstParts && count.tinyPivots == 0 && count.negative > 0 && count.negative % 2 == 1 &&
            shown % 2 == 0 && !count.circulatory) {
          int root = -1;
          for (int m : zeros) {
            const auto& mode = modes.result.modes[m];
            if (mode.stability == eigen::Stability::Critical && mode.lambda.real() > 0.0 &&
                (mode.lambda.imag() == 0.0 || std::abs(mode.lambda.imag()) <= mode.eigenvalueError) &&
                (root < 0 || mode.lambda.real() > modes.result.modes[root].lambda.real()))
              root = m;
          }
          if (root >= 0) {
            modes.result.modes[root].stability = eigen::Stability::Divergence;
            --report.critical, ++report.divergent;
          }
        }
      }
      return report;
    }
  }

  // 2. Singular at rest: a free motion (unrestrained) or a vibration that
  // rounding of the coupled K cannot resolve (ill-conditioned).
  const StructureModes& at = spinning ? rest : modes;
  const auto z = zeroModes(at);
  const auto character = reduced.characterise(at);
  int rigid = 0, worst = -1;
  for (int m : z) {
    if (modeStrain(character[m]) <= kStrainSplit) ++rigid;
    else if (worst < 0 || modeStrain(character[m]) < modeStrain(character[worst]))
      worst = m;
  }
  std::ostringstream os;
  if (rigid > report.expected || worst < 0) {
    // The first free motion beyond the expected ones, by the substructure
    // that carries most of its kinetic energy.
    int m = z.back();
    for (int k : z)
      if (modeStrain(character[k]) <= kStrainSplit) m = k;
    const std::size_t k = argmax(character[m].kineticShare);
    const auto u = reduced.expand(at, m);
    os << "unrestrained: " << rigid << " rigid-body motion" << (rigid == 1 ? "" : "s") << " at rest where the structure has "
       << report.expected << " (" << (structure.freeFloating() ? "free C: 6" : "C clamped: 0")
       << ", plus one per free-turning wheel); substructure '" << structure.substructure(k).name
       << "' moves freely (" << freeMotion(structure, k, *u[k]) << " of its motion, "
       << character[m].kineticShare[k] << " of the mode's kinetic energy): clamp it (\"Clamp\", "
       << "\"Boundary Conditions\"), attach it, or let C float (\"Free Reference\")";
    // A strain-free zero of a clamped mesh: the reduced Hex20's zero-energy
    // modes, which communicate through a column one element across.
    if (hasReducedHex20(structure, k))
      os << "; or, clamped as it may be, the zero-energy (hourglass) modes of its reduced-integration Hex20 "
            "elements (Hex20: Reduced, a deck's C3D20R), which a mesh one element across lets through: set "
            "\"Hex20: Full\" on its element set, or mesh two elements across";
    if (unstable && zeros.size() <= static_cast<std::size_t>(report.expected))
      os << " (seen at speed as unstable modes: the spin's softening of these zero modes)";
    throw InputError(os.str());
  }
  // Ill-conditioned: the mode deforms substructure j (its strain well above
  // rounding) but its frequency is below what the coupled K resolves. The
  // frequency it has is about strain_j * scale_j; the coupled K's rounding
  // is set by the stiffest substructure's scale.
  const auto& strain = character[worst].relativeStrain;
  const std::size_t j = mostStrained(character[worst]);
  std::size_t stiffest = 0;
  for (std::size_t k = 1; k < structure.numSubstructures(); ++k)
    if (stiffnessScale(structure, k) > stiffnessScale(structure, stiffest)) stiffest = k;
  const double condition = stiffnessScale(structure, stiffest) / (strain[j] * stiffnessScale(structure, j));
  os.precision(2);
  os << "ill-conditioned stiffness: " << z.size() << " frequencies indistinguishable from zero at rest where the structure has "
     << report.expected << " rigid-body motions, but they deform substructure '" << structure.substructure(j).name
     << "' (strain " << strain[j] << " of its stiffness scale, not a rigid motion). The stiffness scales (||K||/||M||) "
     << "span from '" << structure.substructure(stiffest).name << "' (" << stiffnessScale(structure, stiffest)
     << " (rad/s)^2) to '" << structure.substructure(j).name << "' (" << stiffnessScale(structure, j)
     << "): condition estimate " << condition << ", beyond what the coupled model resolves. Reduce '"
     << structure.substructure(stiffest).name
     << "' (Craig-Bampton or Guyan: its constraint modes carry its near-rigid motion exactly) or model it rigid (R)";
  throw NumericalError(os.str());
}

void checkMass(const synthesis::AssembledStructure& structure, const synthesis::SynthesizedStructure& reduced) {
  const double eps = std::numeric_limits<double>::epsilon();
  for (std::size_t k = 0; k < structure.numSubstructures(); ++k) {
    const auto* sub = structure.assembled(k);
    if (!sub || reduced.reductions().at(k).basis != "Full") continue;
    // The substructure's size (bounding box diagonal) and mass.
    const auto& dofs = sub->dofs();
    std::array<double, 6> box{1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
    for (std::size_t i = 0; i < dofs.nodes(); ++i)
      for (int d = 0; d < 3; ++d) {
        box[d] = std::min(box[d], dofs.coordinates[3 * i + d]);
        box[3 + d] = std::max(box[3 + d], dofs.coordinates[3 * i + d]);
      }
    double size2 = 0.0;
    for (int d = 0; d < 3; ++d) size2 += std::pow(box[3 + d] - box[d], 2);
    const auto& M = *sub->M();
    const auto map = M.getRowMap();
    Vector diag(map);
    M.getLocalDiagCopy(diag);
    auto d = diag.getData(0);
    double localTrace[2] = {0, 0}, trace[2] = {0, 0};
    for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
      const auto c = static_cast<int>(dofs.components.at(static_cast<std::size_t>(map->getGlobalElement(static_cast<LocalOrdinal>(l)))));
      localTrace[c >= 3] += d[l];
    }
    Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, 2, localTrace, trace);
    const double mass = trace[0] / 3.0;  // every node's three translations
    long long worst[2] = {-1, -1}, global[2] = {-1, -1};
    for (std::size_t l = 0; l < map->getNodeNumElements() && worst[0] < 0; ++l) {
      const auto g = map->getGlobalElement(static_cast<LocalOrdinal>(l));
      const auto c = static_cast<int>(dofs.components.at(static_cast<std::size_t>(g)));
      const double floor = 1e3 * eps * mass * (c >= 3 ? std::max(size2, eps) : 1.0);
      if (!(d[l] > floor)) worst[0] = g, worst[1] = c;
    }
    Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_MAX, 2, worst, global);
    if (global[0] >= 0) {
      const auto nodes = dofs.rowNodes();
      const auto node = dofs.nodeIds.at(static_cast<std::size_t>(nodes.at(static_cast<std::size_t>(global[0]))));
      std::ostringstream os;
      os << "singular mass: substructure '" << structure.substructure(k).name << "' (Full basis) has DOFs without mass, e.g. node "
         << node << " " << fem::componentName(static_cast<fem::Component>(global[1]))
         << " (its M diagonal is below 1e3 eps of the substructure's mass " << mass
         << (global[1] >= 3 ? " x size^2" : "")
         << "): give it inertia (\"Rotary Inertia: true\", a point mass's \"Inertia\"), or reduce the substructure "
            "(Craig-Bampton, Guyan or Admissible condense massless DOFs statically)";
      throw InputError(os.str());
    }
  }
}

}  // namespace cms::analysis
