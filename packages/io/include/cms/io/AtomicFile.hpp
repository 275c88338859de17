// A result file written under a temporary name and renamed by commit(), so
// that a run that fails (or is killed) leaves no half-written file behind:
// the drivers' rule "only a success writes files" (doc/user-guide.md,
// "Exit codes"). Written by one rank (rank 0).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace cms::io {

class AtomicFile {
public:
  /// Opens `path`.tmp; cms::InputError naming `path` when it cannot be written.
  explicit AtomicFile(std::filesystem::path path);
  std::ostream& stream() { return out_; }
  /// Closes and renames to the final name.
  void commit();
  /// Without commit(): the temporary file is removed.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

private:
  std::filesystem::path path_, tmp_;
  std::ofstream out_;
};

/// One CSV field: quoted (with "" for ") when it holds a comma, quote or newline.
std::string csvField(const std::string& s);

}  // namespace cms::io
