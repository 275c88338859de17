// What the drivers' command lines share (cms and its subcommands, campbell,
// bench_rotor): comma-separated lists checked item by item, with messages
// naming the option, and --plot through plot_results.py. Header-only, like
// DataDirectory.hpp: the drivers are programs, not a library.
#pragma once

#include <cerrno>
#include <cmath>
#include <climits>
#include <cstdlib>
#include <functional>
#include <memory>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <spawn.h>
#include <unistd.h>
#include <sys/wait.h>

#include <Teuchos_CommandLineProcessor.hpp>

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

/// Numeric options read as text and converted whole once the command line
/// is parsed. Teuchos' own int and double options read the leading digits
/// and dropped the rest (--steps=5abc ran 5 speeds, --length=500mm a 500 m
/// shaft, --max-factor=1,5 a sweep to 1), and an empty or out-of-range value
/// escaped as an internal error (found by a review). A value must be the
/// whole text: an integer within int's range, or a finite decimal number
/// (no hexadecimal, no inf or nan).
class NumericOptions {
public:
  template <class T>
  void declare(Teuchos::CommandLineProcessor& clp, const char* name, T* value, const char* help) {
    static_assert(std::is_same_v<T, int> || std::is_same_v<T, double>, "int or double options");
    std::ostringstream shown;  // the default as --help shows it
    shown << *value;
    auto text = std::make_shared<std::string>(shown.str());
    clp.setOption(name, text.get(), help);
    items_.push_back({name, shown.str(), text, [value](const std::string& option, const std::string& t) {
                        *value = static_cast<T>(parse(option, t, std::is_same_v<T, int>));
                      }});
  }
  /// After a successful parse: every option given is converted, or
  /// cms::InputError names the first that is not a number of its kind (an
  /// option left at its shown default keeps its value, unrounded).
  void convert() const {
    for (const auto& i : items_)
      if (*i.text != i.shown) i.set("--" + i.name, *i.text);
  }

private:
  static double parse(const std::string& option, const std::string& t, bool integer) {
    const bool plain = !t.empty() && t.find_first_not_of(integer ? "+-0123456789" : "+-0123456789.eE") == std::string::npos;
    char* end = nullptr;
    errno = 0;
    const double v = integer ? static_cast<double>(std::strtoll(t.c_str(), &end, 10)) : std::strtod(t.c_str(), &end);
    CMS_INPUT_CHECK(!plain || end != t.c_str() + t.size() || errno == ERANGE || !std::isfinite(v) ||
                        (integer && (v < INT_MIN || v > INT_MAX)),
                    option << "=" << t << ": not " << (integer ? "an integer" : "a number")
                           << (t.empty() ? " (no value given)" : ""));
    return v;
  }
  struct Item {
    std::string name, shown;
    std::shared_ptr<std::string> text;
    std::function<void(const std::string&, const std::string&)> set;
  };
  std::vector<Item> items_;
};

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
