// The files of one run, written whole or not at all: each under a
// temporary name while it is written, then, once every one of them is
// complete, all renamed to their names (commit). A run that fails (or is
// killed, or meets a full disk) leaves none of them behind: the drivers'
// rule "only a success writes files" (doc/user-guide.md, "Exit codes").
// Before, each file was renamed as soon as it was written, so a run that
// failed on its third file left the first two, and a stream that failed
// mid-file (a full disk, a file-size limit) was renamed cut short: a VTU
// cut in the middle of its XML, with exit 0 (found by a review).
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cms/core/CsvField.hpp"

namespace Teuchos { template <class Ordinal> class Comm; }

namespace cms::io {

class OutputFiles {
public:
  OutputFiles() = default;
  /// A stream to `path`.tmp (12 significant digits). A file that cannot be
  /// opened or written is not an error here: commit() finds it, so that a
  /// collective writer never throws on one rank alone.
  std::ostream& open(const std::filesystem::path& path);
  /// Closes every file; if each was written whole, renames each to its
  /// name; else removes every temporary and throws cms::InputError naming
  /// the first that failed. Returns the names written.
  std::vector<std::string> commit();
  /// The same, collective: rank 0's files committed, the outcome shared,
  /// and the same cms::InputError thrown on every rank when it failed.
  std::vector<std::string> commit(const Teuchos::Comm<int>& comm);
  /// Temporaries not committed are removed.
  ~OutputFiles();
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

private:
  struct File {
    std::filesystem::path path, tmp;
    std::unique_ptr<std::ofstream> out;
  };
  std::vector<File> files_;
  void discard();
};

/// One CSV field: quoted (with "" for ") when it holds a comma, quote or
/// newline (cms/core/CsvField.hpp).
using cms::csvField;

}  // namespace cms::io
