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
  // Every file is whole: now each must take its name. A name held by a
  // directory (or a rename refused for another reason) once threw past
  // the collective commit after the files before it were renamed: partial
  // output, an "internal error", and on two ranks a hang (found by a
  // review). Names are checked first; a rename that still fails takes
  // back the files renamed before it (their earlier versions, replaced,
  // are gone either way), so the run leaves none of its files.
  const auto refuse = [&](const File& f, const std::string& why, std::size_t renamed) {
    const std::string name = f.path.string();
    for (std::size_t i = 0; i < renamed; ++i) {
      std::error_code ec;
      std::filesystem::remove(files_[i].path, ec);
    }
    discard();  // the temporaries not yet renamed
    throw InputError(name + ": cannot replace (" + why + "); no files written");
  };
  for (const auto& f : files_) {
    std::error_code ec;
    if (std::filesystem::is_directory(f.path, ec)) refuse(f, "a directory has its name", 0);
  }
  std::vector<std::string> written;
  for (std::size_t i = 0; i < files_.size(); ++i) {
    std::error_code ec;
    std::filesystem::rename(files_[i].tmp, files_[i].path, ec);
    if (ec) refuse(files_[i], ec.message(), i);
    written.push_back(files_[i].path.string());
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
    } catch (const std::exception& e) {
      // Anything else (memory) is shared too: rank 0 alone must not leave
      // the others waiting in the broadcast below.
      why = std::string("writing the run's files failed: ") + e.what();
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
