// The results of a modal analysis (analysis::ModalResult) as files an
// engineer or a script reads: <name>.json (every number with its accuracy:
// residual, "error_estimate", "true_error", "coverage"), <name>-modes.csv and
// <name>-coverage.csv (doc/user-guide.md, "Output files"). JSON goes through
// nlohmann-json (escaping and number formats right by construction); each
// is staged in the run's OutputFiles, which writes them all or none. Rank 0
// only.
#pragma once

#include <filesystem>
#include <string>

#include "cms/analysis/ModalAnalysis.hpp"
#include "cms/io/OutputFiles.hpp"

namespace cms::io {

/// What the JSON records about how it was produced.
struct RunRecord {
  std::string scenePath, sceneText, name, units, version;
  int ranks = 1;
  double peakMemoryMiB = 0.0;
};

/// Each staged in `files` under `file` (written by files.commit()).
void writeModesJson(OutputFiles& files, const std::filesystem::path& file, const analysis::ModalResult& r,
                    const RunRecord& run);
void writeModesCsv(OutputFiles& files, const std::filesystem::path& file, const analysis::ModalResult& r);
void writeCoverageCsv(OutputFiles& files, const std::filesystem::path& file, const analysis::ModalResult& r);

}  // namespace cms::io
