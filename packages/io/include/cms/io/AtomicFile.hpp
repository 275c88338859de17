// One result file written under a temporary name and renamed by commit(), so
// that a run that fails (or is killed) leaves no half-written file behind
// (OutputFiles with one file; a run with several uses OutputFiles, so that
// they are all written or none). Written by one rank (rank 0).
#pragma once

#include <filesystem>
#include <string>

#include "cms/io/OutputFiles.hpp"

namespace cms::io {

class AtomicFile {
public:
  /// Opens `path`.tmp; cms::InputError naming `path` when it cannot be written.
  explicit AtomicFile(std::filesystem::path path);
  std::ostream& stream() { return *out_; }
  /// Closes and renames to the final name; a failed write is a
  /// cms::InputError, and the temporary file is removed.
  void commit() { files_.commit(); }

private:
  OutputFiles files_;
  std::ostream* out_;
};

/// One CSV field: quoted (with "" for ") when it holds a comma, quote or newline.
std::string csvField(const std::string& s);

}  // namespace cms::io
