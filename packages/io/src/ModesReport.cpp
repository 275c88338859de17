#include "cms/io/ModesReport.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "cms/analysis/TruthComparison.hpp"
#include "cms/io/OutputFiles.hpp"

namespace cms::io {

namespace {
constexpr double kTwoPi = 2.0 * M_PI;
using json = nlohmann::ordered_json;  // keys in the order written: the file reads top-down

/// A number, or null when it is not one (no estimate: a zero frequency).
json numberOrNull(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
}  // namespace

void writeModesJson(OutputFiles& files, const std::filesystem::path& file, const analysis::ModalResult& r,
                    const RunRecord& run) {
  const auto& structure = *r.structure;
  const auto& modes = r.modes.result.modes;
  json o;
  o["scene"] = run.scenePath;
  o["scene_text"] = run.sceneText;
  o["name"] = run.name;
  o["units"] = {{"length", "m"}, {"mass", "kg"}, {"time", "s"}, {"frequency", "Hz and rad/s"}};
  o["version"] = run.version;
  o["ranks"] = run.ranks;
  o["timings_s"] = {{"assembly", r.assemblySeconds},
                    {"reduction_and_synthesis", r.reductionSeconds},
                    {"solve", r.modes.seconds},
                    {"error_estimates_and_coverage", r.accuracySeconds},
                    {"error_estimates", r.estimateSeconds}};
  o["peak_memory_mib"] = run.peakMemoryMiB;
  o["speeds"] = json::array();
  for (std::size_t i = 0; i < r.speeds.size(); ++i)
    o["speeds"].push_back({{"name", structure.speeds()[i].name}, {"rad_per_s", r.speeds[i]}});
  o["notes"] = structure.notes();
  o["substructures"] = json::array();
  for (const auto& s : r.reduced->reductions()) {
    std::vector<double> hz;
    for (double w : s.frequencyEstimates) hz.push_back(w / kTwoPi);
    o["substructures"].push_back({{"name", s.name},
                                  {"kind", s.kind},
                                  {"physical_dofs", s.physicalDofs},
                                  {"basis", s.basis},
                                  {"coordinates", s.coordinates},
                                  {"attachment_dofs", s.attachmentDofs},
                                  {"basis_seconds", s.seconds},
                                  {"basis_report", s.eigensolverReport},
                                  {"basis_bytes", s.basisBytes},
                                  {"basis_adopted_prestress_factor", s.adoptedPrestressFactor},
                                  {"estimates_adopted_prestress_factor", s.estimatesAdoptedPrestressFactor},
                                  {"projected_from_prototype", s.projectedFromPrototype},
                                  {"frequency_estimates_hz", hz},
                                  {"dropped", s.dropped}});
    // A copy's basis turned from its prototype's (theory §15.2), or why not.
    if (!s.turnedFrom.empty()) o["substructures"].back()["basis_turned_from"] = s.turnedFrom;
    if (!s.notTurned.empty()) o["substructures"].back()["basis_not_turned"] = s.notTurned;
  }
  json coverage = {{"cutoff_hz", r.cutoff / kTwoPi}, {"substructures", json::array()}};
  for (const auto& c : r.coverage)
    coverage["substructures"].push_back({{"name", c.name},
                                         {"basis", c.basis},
                                         {"sturm_count", c.sturmCount},
                                         {"represented", c.represented},
                                         {"coordinates", c.coordinates},
                                         {"verdict", c.verdict}});
  if (r.truthCount >= -1) {
    coverage["structure_truth_count"] = r.truthCount;
    coverage["structure_reduced_count"] = r.reducedCount;
    coverage["structure_count_band"] = r.countBand;  // reduced frequencies counted up to cutoff (1 + band)
  } else if (const std::string why = analysis::truthCountNote(r.truthCount); !why.empty()) {
    coverage["structure_truth_count"] = nullptr;  // asked, not countable (-3 damped, -4 K indefinite)
    coverage["structure_count_note"] = why;
  }
  if (r.truthMissing >= 0) coverage["truth_unpaired_in_range"] = r.truthMissing;
  if (r.truthUnmatched >= 0) coverage["reduced_unmatched"] = r.truthUnmatched;
  o["coverage"] = coverage;
  o["solver"] = r.modes.result.solver;
  o["path"] = r.modes.path;
  o["status"] = toString(r.modes.result.status);
  o["reason"] = r.modes.result.reason;
  // Damping (theory §13): whether the structure has any, and its least
  // damping ratio over the vibration modes (< 0: unstable).
  o["damped"] = !r.reduced->damping().is_null();
  o["least_damping_ratio"] = r.modes.result.leastDampingRatio();
  // The energy bound on every growth rate, where a damped dense solve
  // sought it (theory §13.3): null where not shown.
  if (!r.modes.result.energyBound.note.empty())
    o["energy_bound"] = {{"shown", r.modes.result.energyBound.shown},
                         {"growth", r.modes.result.energyBound.shown ? json(r.modes.result.energyBound.growth)
                                                                     : json(nullptr)},
                         {"note", r.modes.result.energyBound.note}};
  o["modes"] = json::array();
  for (std::size_t m = 0; m < modes.size(); ++m) {
    const auto& md = modes[m];
    json j = {{"hz", md.hz},
              {"rad_per_s", md.omega},
              {"growth_rate", md.growthRate},
              {"damping_ratio", md.dampingRatio},
              {"log_decrement", numberOrNull(md.logDecrement)},  // null: a real (overdamped) lambda
              {"stability", toString(md.stability)},
              {"residual", md.residual},
              {"error_estimate", r.estimates[m] >= 0.0 ? json(r.estimates[m]) : json(nullptr)}};
    // The growth rate's uncertainty (theory §13.3): beyond it an
    // instability; refined: by two-sided inverse iteration.
    if (md.growthTolerance > 0.0) {
      j["growth_uncertainty"] = md.growthTolerance;
      j["growth_refined"] = md.refinedError > 0.0;
      j["growth_undecided"] = md.undecided;
    }
    // How far the solve can have left the eigenvalue from the reduced
    // model's exact one (1/s; theory §5, "Stiff rows"): the two-sided bound
    // where the mode was refined, else the first-order estimate ||r|| ||q||
    // / |q^H Q'(lambda) q|.
    // Not for a zero (rigid or critical), which has no relative accuracy
    // and whose first-order estimate means nothing.
    if ((md.refinedError > 0.0 || md.eigenvalueError > 0.0) && md.stability != eigen::Stability::RigidBody &&
        md.stability != eigen::Stability::Critical) {
      j["eigenvalue_error"] = numberOrNull(md.reportedError());
      j["eigenvalue_error_kind"] = md.refinedError > 0.0 ? "refined bound" : "first order";
    }
    // The rigorous bound (theory §11.8), only where the structure is SPD.
    if (m < r.accuracy.size() && r.accuracy[m].bound >= 0.0) {
      j["error_bound"] = r.accuracy[m].bound;
      j["error_bound_kind"] = r.accuracy[m].boundKind;
    }
    if (m < r.trueErrors.size()) j["true_error"] = numberOrNull(r.trueErrors[m]);
    j["frame_artefact"] = r.character[m].frameArtefact;
    j["whirl"] = r.whirls[m];
    j["kinetic_share"] = r.character[m].kineticShare;
    // Per copied item, the mode's cyclic harmonic (theory §15.3).
    for (const auto& c : r.character[m].cyclic)
      j["cyclic"][c.group] = {{"label", c.label()}, {"harmonic", c.dominant}, {"share", c.share}};
    o["modes"].push_back(j);
  }
  // Text that is not UTF-8 (a Latin-1 comment in the scene, recorded in
  // scene_text) is written with U+FFFD in its place: JSON is UTF-8, and the
  // exception nlohmann throws otherwise ended a finished run as an internal
  // error, and under MPI hung the ranks waiting for rank 0 (found by a review).
  files.open(file) << o.dump(2, ' ', false, json::error_handler_t::replace) << '\n';
}

void writeModesCsv(OutputFiles& files, const std::filesystem::path& file, const analysis::ModalResult& r) {
  auto& out = files.open(file);
  out << "mode,hz,rad_per_s,growth_rate,damping_ratio,log_decrement,stability,residual,error_estimate,error_bound,"
         "frame_artefact";
  for (const auto& s : r.reduced->reductions()) out << ",share_" << csvField(s.name);
  if (!r.character.empty())
    for (const auto& c : r.character.front().cyclic) out << ",cyclic_" << csvField(c.group);
  out << '\n';
  const auto& modes = r.modes.result.modes;
  for (std::size_t m = 0; m < modes.size(); ++m) {
    const auto& md = modes[m];
    out << m + 1 << ',' << md.hz << ',' << md.omega << ',' << md.growthRate << ',' << md.dampingRatio << ','
        << md.logDecrement << ',' << toString(md.stability) << ','
        << md.residual << ',' << (r.estimates[m] >= 0.0 ? r.estimates[m] : std::nan("")) << ','
        << (m < r.accuracy.size() && r.accuracy[m].bound >= 0.0 ? r.accuracy[m].bound : std::nan("")) << ','
        << r.character[m].frameArtefact;
    for (double v : r.character[m].kineticShare) out << ',' << v;
    for (const auto& c : r.character[m].cyclic) out << ',' << csvField(c.label());
    out << '\n';
  }
}

void writeCoverageCsv(OutputFiles& files, const std::filesystem::path& file, const analysis::ModalResult& r) {
  auto& out = files.open(file);
  out << "substructure,basis,cutoff_hz,sturm_count,represented,coordinates,verdict\n";
  for (const auto& c : r.coverage)
    out << csvField(c.name) << ',' << csvField(c.basis) << ',' << c.cutoff / kTwoPi << ',' << c.sturmCount
               << ',' << c.represented << ',' << c.coordinates << ',' << csvField(c.verdict) << '\n';
}

}  // namespace cms::io
