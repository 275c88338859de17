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
  std::string name;          ///< "Name", default the file's stem
  std::string units = "SI";  ///< the only system supported: m, kg, s, N, rad
  synthesis::StructureDescription structure;
  /// "Analysis": the synthesis solve parameters ("Number of Modes",
  /// "Solver", "Dense Limit") and the speed factor applied to every
  /// nominal spin rate.
  Teuchos::ParameterList solve = Teuchos::ParameterList("Solve");
  double speedFactor = 1.0;
  /// "Output": directory (relative to the scene; empty: the caller's
  /// choice) and which files to write.
  std::string outputDirectory;
  bool json = true, csv = true;

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

}  // namespace cms::scene
