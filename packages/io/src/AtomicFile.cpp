#include "cms/io/AtomicFile.hpp"

#include <iomanip>

#include "cms/core/Error.hpp"

namespace cms::io {

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)), tmp_(path_.string() + ".tmp") {
  out_.open(tmp_);
  CMS_INPUT_CHECK(!out_, path_.string() << ": cannot write");
  out_ << std::setprecision(12);
}

void AtomicFile::commit() {
  out_.close();
  CMS_INPUT_CHECK(out_.fail(), path_.string() << ": writing failed (disk full?)");
  std::filesystem::rename(tmp_, path_);
}

AtomicFile::~AtomicFile() {
  if (out_.is_open()) {
    out_.close();
    std::error_code ec;
    std::filesystem::remove(tmp_, ec);
  }
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) {
    if (c == '"') o += '"';
    o += c;
  }
  return o + "\"";
}

}  // namespace cms::io
