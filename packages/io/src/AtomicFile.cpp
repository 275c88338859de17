#include "cms/io/AtomicFile.hpp"

#include <iomanip>

#include "cms/core/Error.hpp"

namespace cms::io {

AtomicFile::AtomicFile(std::filesystem::path path) : out_(&files_.open(path)) {
  CMS_INPUT_CHECK(!*out_, path.string() << ": cannot write");
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
