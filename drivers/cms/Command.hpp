// What every `cms` subcommand does before and after its own steps
// (drivers/cms/main.cpp): its own options and --help, the scene read and
// checked before anything is computed, the output directory, the banner
// line, and --plot. The subcommands (modes.cpp, campbell.cpp, compare.cpp,
// truncate.cpp) only read, call the library and print.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "../CommandLine.hpp"  // positiveIntegers, positiveNumbers, plotCsv
#include "cms/core/Error.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace Teuchos { class CommandLineProcessor; }

namespace cms::drivers {

/// One subcommand's command line: the options it declares (and only those,
/// plus the common ones) are parsed by Teuchos::CommandLineProcessor, and
/// `--help` prints them with their defaults (not Teuchos' own debugging
/// options).
class Options {
public:
  Options(std::string command, std::string summary);
  void add(const char* name, std::string* value, const char* help);
  void add(const char* name, int* value, const char* help);
  void add(const char* name, double* value, const char* help);
  /// --name / --no-name
  void flag(const char* name, bool* value, const char* help);
  /// --plot for the subcommands that draw their CSV table.
  void plotOption() { flag("plot", &plot_, "also draw the CSV table as a PNG (Debian's python3-matplotlib)"); }
  bool plot() const { return plot_; }

  const std::string& command() const { return command_; }
  void printHelp(std::ostream& os) const;

private:
  friend struct SceneRun;
  std::string command_, summary_;
  struct Entry {
    std::string name, help, fallback;
    std::function<void(Teuchos::CommandLineProcessor&)> declare;
  };
  std::vector<Entry> entries_;
  NumericOptions numbers_;  // the int and double options, converted after the parse
  bool plot_ = false;
};

/// The scene of one run, read after the options: [SCENE] is the first
/// argument after the subcommand when it does not start with '-', else the
/// built-in spacecraft (found next to the program or under share/cms).
struct SceneRun {
  scene::Scene scene;
  std::filesystem::path outDir;
  bool root = true;
  bool timers = false;

  /// Parses argv[2..] against `options` (and the common --output,
  /// --mesh-parameters, --timers), reads the scene and makes the output
  /// directory. Returns the exit code when the program ends here (--help
  /// printed: 0; a wrong command line: 2), nothing when the run goes on.
  /// Throws cms::InputError for a bad scene.
  std::optional<int> start(Options& options, int argc, char* argv[]);

  /// The scene's structure assembled across all ranks: each substructure's
  /// matrices per unit speed, centrifugal prestress first (theory §11.4).
  /// Collective. Its errors name the scene file (namingScene).
  synthesis::AssembledStructure assemble() const;

  /// f(), with the scene file named at the front of a cms::InputError or
  /// NumericalError it throws: the substructure, set or key the library
  /// names is in that file.
  template <class F>
  auto namingScene(F&& f) const -> decltype(f()) {
    try {
      return f();
    } catch (const InputError& e) {
      throw InputError(scene.path + ": " + e.what());
    } catch (const NumericalError& e) {
      throw NumericalError(scene.path + ": " + e.what());
    }
  }
};

/// The output directory this run created (empty if it existed before).
std::filesystem::path& createdOutput();
/// A failed run leaves nothing behind: not even the directory it created
/// for its files, when it stayed empty.
void removeCreatedOutputIfEmpty();

/// The built-in default scene (the spacecraft).
std::string defaultScene();

/// --plot: drivers/plot_results.py `kind` on `csv`, writing a PNG beside it
/// (`extra`: the script's own options, one argument each, e.g.
/// {"--orders=1,2", "--axis=hz"}).
void plot(const Options& options, const std::string& kind, const std::filesystem::path& csv,
          const std::vector<std::string>& extra = {});

/// "[t s] " for progress lines.
std::string stamp(double seconds);

}  // namespace cms::drivers
