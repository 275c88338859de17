// A scene: what one analysis of one structure needs, read from a YAML file
// (Teuchos ParameterList YAML; XML by extension .xml) and checked key by key
// before anything is computed (doc/user-guide.md, "Scenes"). It names the
// substructures — built-in frame beams, meshed finite-element models or
// rigid rotors — their kinds, parents, attachments, spins and reductions,
// what to compute and where to write it. Relative paths resolve against the
// scene file.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/synthesis/Structure.hpp"

namespace cms::scene {

struct Scene {
  std::string path;          ///< the file it was read from
  /// The text read (read, parse; empty from fromParameters): what the
  /// results record as the scene, not the file as it is when they are
  /// written (a review: a scene edited during a run was recorded edited).
  std::string text;
  std::string name;          ///< "Name", default the file's stem
  std::string units = "SI";  ///< the only system supported: m, kg, s, N, rad
  synthesis::StructureDescription structure;
  /// "Analysis": the synthesis solve parameters ("Number of Modes",
  /// "Solver", "Dense Limit") and the speed factor applied to every
  /// nominal spin rate.
  Teuchos::ParameterList solve = Teuchos::ParameterList("Solve");
  double speedFactor = 1.0;
  /// "Analysis/Target Accuracy": > 0, the estimated relative error every
  /// mode must reach (cms modes enriches the bases); 0 off.
  double targetAccuracy = 0.0;
  /// "Output": directory (relative to the scene; empty: the caller's
  /// choice) and which files to write.
  std::string outputDirectory;
  bool json = true, csv = true;
  /// The size of the model before it is assembled: its physical DOFs (6 a
  /// node with frame elements, 3 without) and a lower bound of the memory
  /// one rank needs for it (kBytesPerDof each, measured on frame models:
  /// matrices, factor and vectors). Scene::fromParameters refuses a scene
  /// whose bound exceeds availableMemoryBytes(), naming the largest
  /// substructure's size key; drivers print progress above kLargeDofs.
  long long estimatedDofs = 0;
  double estimatedBytes = 0.0;
  static constexpr double kBytesPerDof = 1000.0;
  static constexpr long long kLargeDofs = 100000;

  /// Reads and checks the scene; throws cms::InputError naming the file and
  /// the key path (or the YAML parser's line) for anything malformed.
  static Scene read(const std::string& path);
  /// The same with these "Mesh Parameters" (name -> value) set on every
  /// substructure meshed from a .geo script, over the file's own (a mesh
  /// size study on one scene: bench_rotor, `cms --mesh-parameters`).
  static Scene read(const std::string& path, const std::map<std::string, double>& meshParameters);
  /// The same from the text of a scene file (`path` for messages and
  /// relative paths).
  static Scene parse(const std::string& text, const std::string& path);
  /// The same from a ParameterList (`path` only for messages and relative
  /// paths).
  static Scene fromParameters(const Teuchos::ParameterList& scene, const std::string& path);
};

/// Memory this process may still use (bytes): cms::availableMemoryBytes
/// (cms/core/PeakMemory.hpp).
double availableMemoryBytes();

}  // namespace cms::scene
