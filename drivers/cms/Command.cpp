#include "Command.hpp"

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <Teuchos_CommandLineProcessor.hpp>
#include <Teuchos_DefaultComm.hpp>

#include "../DataDirectory.hpp"
#include "cms/core/Error.hpp"

namespace cms::drivers {

namespace {
template <class T>
std::string text(const T& v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

/// "name=value,...": the "Mesh Parameters" of every substructure meshed from a .geo.
std::map<std::string, double> meshParameters(const std::string& text) {
  std::map<std::string, double> out;
  std::istringstream is(text);
  std::string item;
  while (std::getline(is, item, ',')) {
    const auto eq = item.find('=');
    char* end = nullptr;
    const double v = eq == std::string::npos ? 0.0 : std::strtod(item.c_str() + eq + 1, &end);
    CMS_INPUT_CHECK(eq == std::string::npos || eq == 0 || end == item.c_str() + eq + 1 || *end != '\0' ||
                        !std::isfinite(v),
                    "--mesh-parameters: \"" << item << "\" is not name=number");
    std::string name = item.substr(0, eq);
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    CMS_INPUT_CHECK(name.empty(), "--mesh-parameters: \"" << item << "\" has no name");
    out[name] = v;
  }
  return out;
}
}  // namespace

Options::Options(std::string command, std::string summary) : command_(std::move(command)), summary_(std::move(summary)) {}

void Options::add(const char* name, std::string* value, const char* help) {
  entries_.push_back({name, help, "\"" + *value + "\"",
                      [=](Teuchos::CommandLineProcessor& c) { c.setOption(name, value, help); }});
}
// Numbers are taken as text and converted whole after the parse
// (NumericOptions): Teuchos' own int and double options dropped trailing text.
void Options::add(const char* name, int* value, const char* help) {
  entries_.push_back({name, help, text(*value),
                      [=, this](Teuchos::CommandLineProcessor& c) { numbers_.declare(c, name, value, help); }});
}
void Options::add(const char* name, double* value, const char* help) {
  entries_.push_back({name, help, text(*value),
                      [=, this](Teuchos::CommandLineProcessor& c) { numbers_.declare(c, name, value, help); }});
}
void Options::flag(const char* name, bool* value, const char* help) {
  const std::string no = std::string("no-") + name;
  entries_.push_back({std::string(name) + "|--" + no, help, *value ? "on" : "off",
                      [=](Teuchos::CommandLineProcessor& c) { c.setOption(name, no.c_str(), value, help); }});
}

void Options::printHelp(std::ostream& os) const {
  os << "usage: cms " << command_ << " [SCENE] [options]\n\n" << summary_ << "\n\n"
     << "SCENE: a YAML scene (doc/user-guide.md, \"Scenes\"); default: the built-in spacecraft\n"
     << "       (<prefix>/share/cms/scenes/spacecraft.yaml)\n\noptions:\n";
  for (const auto& e : entries_) {
    const std::string flag = "--" + e.name + (e.name.find('|') == std::string::npos ? "=" : "");
    os << "  " << flag << (flag.size() < 28 ? std::string(28 - flag.size(), ' ') : "\n" + std::string(30, ' '))
       << e.help << " (default " << e.fallback << ")\n";
  }
}

std::optional<int> SceneRun::start(Options& options, int argc, char* argv[]) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  root = comm->getRank() == 0;
  // 1. The command line: [SCENE] then this subcommand's options and the common ones.
  std::string scenePath, output, meshText;
  int first = 2;
  if (argc > 2 && argv[2][0] != '-') scenePath = argv[first++];
  options.add("output", &output, "results directory (default: the scene's \"Output\", else ./cms-results)");
  options.add("mesh-parameters", &meshText,
              "name=value,...: \"Mesh Parameters\" of every substructure meshed from a .geo (e.g. h=0.01)");
  options.flag("timers", &timers, "print the Teuchos::TimeMonitor summary at the end");
  for (int i = first; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      if (root) options.printHelp(std::cout);
      return ExitSuccess;
    }
  Teuchos::CommandLineProcessor clp(false, true);
  for (const auto& e : options.entries_) e.declare(clp);
  std::vector<char*> rest{argv[0]};
  for (int i = first; i < argc; ++i) rest.push_back(argv[i]);
  std::ostringstream errors;  // Teuchos' message replaced by one naming the subcommand
  std::string why;
  if (clp.parse(static_cast<int>(rest.size()), rest.data(), &errors) != Teuchos::CommandLineProcessor::PARSE_SUCCESSFUL) {
    // Teuchos' message: its first non-empty line names the option.
    std::istringstream lines(errors.str());
    std::string line;
    while (why.empty() && std::getline(lines, line))
      if (line.find_first_not_of(" \t") != std::string::npos) why = line;
  } else {
    try {
      options.numbers_.convert();
    } catch (const InputError& e) {
      why = e.what();
    }
  }
  if (!why.empty()) {
    if (root)
      std::cerr << "cms " << options.command() << ": bad input: " << why << " (cms " << options.command()
                << " --help lists the options)\n";
    return ExitInputError;
  }
  // 2. The scene, checked key by key before anything is computed.
  if (scenePath.empty()) scenePath = defaultScene();
  const auto mesh = meshParameters(meshText);
  scene = scene::Scene::read(scenePath, mesh);
  if (!mesh.empty()) {
    bool used = false;
    for (const auto& s : scene.structure.substructures)
      used = used || (s.model && s.model->mesh && s.model->mesh->source.size() > 4 &&
                      s.model->mesh->source.compare(s.model->mesh->source.size() - 4, 4, ".geo") == 0);
    CMS_INPUT_CHECK(!used, "--mesh-parameters: no substructure of " << scenePath << " is meshed from a .geo script");
  }
  // --plot draws the CSV table: with Output/CSV false there is none.
  CMS_INPUT_CHECK(options.plot() && !scene.csv,
                  "--plot draws the run's CSV table, and the scene's \"Output/CSV\" is false");
  // 3. The output directory, writable before anything is computed.
  outDir = !output.empty() ? output : (!scene.outputDirectory.empty() ? scene.outputDirectory : "cms-results");
  std::error_code ec;
  if (std::filesystem::create_directories(outDir, ec) && root) createdOutput() = outDir;
  CMS_INPUT_CHECK(ec || !std::filesystem::is_directory(outDir),
                  outDir.string() << ": cannot create the output directory (" << ec.message() << ")");
  // What a mesh reader skipped or assumed (an .inp deck's materials and
  // steps, GENERATE ids it lacks), once per mesh file.
  if (root) {
    std::set<std::string> seen;
    for (const auto& s : scene.structure.substructures)
      if (s.model && s.model->mesh && seen.insert(s.model->mesh->source).second)
        for (const std::string& note : s.model->mesh->notes) std::cout << "cms: note: " << note << "\n";
  }
  if (root)
    std::cout << "cms " << options.command() << ": scene " << scene.path << " (\"" << scene.name << "\", units "
              << scene.units << ", " << scene.structure.substructures.size() << " substructures, "
              << comm->getSize() << " rank(s))\n";
  return std::nullopt;
}

synthesis::AssembledStructure SceneRun::assemble() const {
  return namingScene(
      [&] { return synthesis::AssembledStructure::assemble(scene.structure, Teuchos::DefaultComm<int>::getComm()); });
}

std::filesystem::path& createdOutput() {
  static std::filesystem::path created;
  return created;
}

void removeCreatedOutputIfEmpty() {
  std::error_code ec;
  const auto& dir = createdOutput();
  if (!dir.empty() && std::filesystem::is_empty(dir, ec) && !ec) std::filesystem::remove(dir, ec);
}

// The built-in scene and the plot script: <prefix>/share/cms, found from the
// executable (DataDirectory.hpp), never a source path compiled in.
std::string defaultScene() { return drivers::dataFile("scenes/spacecraft.yaml").string(); }

void plot(const Options& options, const std::string& kind, const std::filesystem::path& csv,
          const std::vector<std::string>& extra) {
  if (options.plot()) plotCsv(kind, csv, extra);
}

std::string stamp(double seconds) {
  std::ostringstream os;
  os << "[" << std::fixed << std::setprecision(2) << seconds << " s] ";
  return os.str();
}

}  // namespace cms::drivers
