// What the drivers' command lines share (cms and its subcommands, campbell,
// bench_rotor): comma-separated lists checked item by item, with messages
// naming the option, and --plot through plot_results.py. Header-only, like
// DataDirectory.hpp: the drivers are programs, not a library.
#pragma once

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <spawn.h>
#include <unistd.h>
#include <sys/wait.h>

#include "DataDirectory.hpp"
#include "cms/core/Error.hpp"

namespace cms::drivers {

/// "a,b,,c" -> {"a", "b", "c"} (empty items dropped).
inline std::vector<std::string> commaList(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream is(text);
  for (std::string item; std::getline(is, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

/// "0.5,1,2" -> {0.5, 1, 2}: every item a finite number above zero (and an
/// integer up to 100000 for T = int); cms::InputError naming `option` for
/// the first that is not, or for an empty list.
template <class T>
std::vector<T> positiveList(const std::string& text, const char* option) {
  std::vector<T> out;
  std::istringstream is(text);
  constexpr bool integer = std::is_integral_v<T>;
  for (std::string item; std::getline(is, item, ',');) {
    char* end = nullptr;
    const double v = integer ? double(std::strtol(item.c_str(), &end, 10)) : std::strtod(item.c_str(), &end);
    CMS_INPUT_CHECK(item.empty() || *end != '\0' || !(v > 0.0) || !std::isfinite(v) || (integer && v > 1e5),
                    option << ": \"" << item << "\" is not a positive " << (integer ? "integer" : "number"));
    out.push_back(static_cast<T>(v));
  }
  CMS_INPUT_CHECK(out.empty(), option << ": no value given");
  return out;
}
inline std::vector<double> positiveNumbers(const std::string& text, const char* option) {
  return positiveList<double>(text, option);
}
inline std::vector<int> positiveIntegers(const std::string& text, const char* option) {
  return positiveList<int>(text, option);
}

#ifdef CMS_PYTHON
/// drivers/plot_results.py `kind` on `csv`, a PNG beside it (`extra`: the
/// script's own options, one argument each); says what it did. With
/// CMS_PYTHON only (the drivers' CMakeLists.txt defines it for the programs
/// that plot). The script is started with its arguments as an argument
/// vector, never through a shell: a scene's Name or an output directory
/// holding a quote once ran as shell commands (found by a review).
inline void plotCsv(const std::string& kind, const std::filesystem::path& csv,
                    const std::vector<std::string>& extra = {}) {
  const auto png = std::filesystem::path(csv).replace_extension(".png");
  std::string script;
  try {
    script = dataFile("plot_results.py").string();
  } catch (const InputError& e) {
    std::cout << "no plot: " << e.what() << '\n';
    return;
  }
  std::vector<std::string> args{CMS_PYTHON, script, kind, csv.string(), png.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::cout.flush();  // the script's output after ours
  pid_t pid = 0;
  int status = 0;
  const bool ran = posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) == 0 &&
                   waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (ran)
    std::cout << "plotted " << png.string() << '\n';
  else
    std::cout << "no plot: " << CMS_PYTHON << " " << script << " " << kind << " failed (plots need Debian's "
              << "python3-matplotlib: apt-get install python3-matplotlib)\n";
}
#endif

}  // namespace cms::drivers
