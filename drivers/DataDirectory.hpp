// Where the drivers find their data (the example scenes, the benchmark
// meshes, plot_results.py) without a path of the source tree compiled in
// (doc/architecture.md, "Install layout"):
//
//   1. $CMS_DATA_DIR, when set (a user's own copy, or a relocated tree);
//   2. <directory of the running executable>/../share/cms: the installed
//      layout (<prefix>/bin/cms, <prefix>/share/cms/scenes/...), and also the
//      build tree, where the configure step makes build/share/cms with links
//      to drivers/scenes, drivers/bench and drivers/plot_results.py
//      (build/drivers/cms -> build/share/cms).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "cms/core/Error.hpp"

namespace cms::drivers {

/// The candidate data directories, in the order they are tried.
inline std::vector<std::filesystem::path> dataDirectories() {
  std::vector<std::filesystem::path> dirs;
  if (const char* v = std::getenv("CMS_DATA_DIR"); v && *v) dirs.emplace_back(v);
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(self.parent_path().parent_path() / "share" / "cms");
  return dirs;
}

/// `relative` (e.g. "scenes/spacecraft.yaml") in the first data directory
/// that has it. Throws cms::InputError naming every place tried.
inline std::filesystem::path dataFile(const std::string& relative) {
  std::string tried;
  for (const auto& dir : dataDirectories()) {
    const auto candidate = dir / relative;
    std::error_code ec;
    if (std::filesystem::exists(candidate, ec)) return candidate.lexically_normal();
    tried += (tried.empty() ? "" : ", ") + candidate.lexically_normal().string();
  }
  CMS_INPUT_CHECK(true, "cannot find the data file " << relative << " (tried: "
                                                     << (tried.empty() ? "nothing" : tried)
                                                     << "); set CMS_DATA_DIR to the directory holding scenes/ and "
                                                        "plot_results.py (<prefix>/share/cms)");
  return {};
}

}  // namespace cms::drivers
