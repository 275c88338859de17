#include "cms/io/OutputFiles.hpp"

#include <iomanip>

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>

#include "cms/core/Error.hpp"

namespace cms::io {

std::ostream& OutputFiles::open(const std::filesystem::path& path) {
  File f{path, path.string() + ".tmp", std::make_unique<std::ofstream>()};
  f.out->open(f.tmp, std::ios::out | std::ios::trunc);
  *f.out << std::setprecision(12);
  files_.push_back(std::move(f));
  return *files_.back().out;
}

void OutputFiles::discard() {
  for (auto& f : files_) {
    if (f.out->is_open()) f.out->close();
    std::error_code ec;
    std::filesystem::remove(f.tmp, ec);
  }
  files_.clear();
}

std::vector<std::string> OutputFiles::commit() {
  std::string failed;
  for (auto& f : files_) {
    // A stream that never opened is in a failed state too: close() then
    // sets failbit again, and both are read as "not written whole".
    const bool opened = f.out->is_open();
    f.out->close();
    if (failed.empty() && (!opened || f.out->fail()))
      failed = f.path.string() + (opened ? ": writing failed (disk full, or a file-size limit?)" : ": cannot write");
  }
  if (!failed.empty()) {
    discard();
    throw InputError(failed + "; no files written");
  }
  std::vector<std::string> written;
  for (auto& f : files_) {
    std::filesystem::rename(f.tmp, f.path);
    written.push_back(f.path.string());
  }
  files_.clear();
  return written;
}

std::vector<std::string> OutputFiles::commit(const Teuchos::Comm<int>& comm) {
  std::vector<std::string> written;
  std::string why;
  if (comm.getRank() == 0) {
    try {
      written = commit();
    } catch (const InputError& e) {
      why = e.what();
    }
  }
  int size = static_cast<int>(why.size());
  Teuchos::broadcast(comm, 0, &size);
  why.resize(static_cast<std::size_t>(size));
  if (size > 0) Teuchos::broadcast(comm, 0, size, why.data());
  if (!why.empty()) throw InputError(why);
  return written;
}

OutputFiles::~OutputFiles() { discard(); }

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
