// Files a test writes and reads back: a fresh folder removed afterwards,
// a file's bytes, one piece of a text replaced (the reader tests, which
// corrupt known-good files one record at a time).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace cms::fixtures {

/// A fresh folder under the system's temporary directory, named from
/// `prefix`, removed with everything in it when the object goes.
class TempDir {
public:
  explicit TempDir(const std::string& prefix = "cms_test") {
    std::string t = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
    if (!mkdtemp(t.data())) throw std::runtime_error("mkdtemp failed");
    path_ = t;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  /// Writes `text` (bytes as given) to `name` in the folder; its path.
  std::string write(const std::string& name, const std::string& text) const {
    const std::string p = (path_ / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  const std::filesystem::path& path() const { return path_; }

private:
  std::filesystem::path path_;
};

/// The bytes of a file.
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// `s` with the first `from` replaced by `to`; a test error when `from` is absent.
inline std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  if (at == std::string::npos) throw std::runtime_error("test text lacks \"" + from + "\"");
  return s.replace(at, from.size(), to);
}

}  // namespace cms::fixtures
