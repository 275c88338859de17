// The results of a modal analysis (analysis::ModalResult) as files an
// engineer or a script reads: <name>.json (every number with its accuracy:
// residual, "error_estimate", "true_error", "coverage"), <name>-modes.csv and
// <name>-coverage.csv (doc/user-guide.md, "Output files"). JSON goes through
// nlohmann-json (escaping and number formats right by construction); every
// file is written atomically (AtomicFile). Rank 0 only.
#pragma once

#include <filesystem>
#include <string>

#include "cms/analysis/ModalAnalysis.hpp"

namespace cms::io {

/// What the JSON records about how it was produced.
struct RunRecord {
  std::string scenePath, sceneText, name, units, version;
  int ranks = 1;
  double peakMemoryMiB = 0.0;
};

void writeModesJson(const std::filesystem::path& file, const analysis::ModalResult& r, const RunRecord& run);
void writeModesCsv(const std::filesystem::path& file, const analysis::ModalResult& r);
void writeCoverageCsv(const std::filesystem::path& file, const analysis::ModalResult& r);

}  // namespace cms::io
