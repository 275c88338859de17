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
  // review). Names are checked first; the earlier results a run replaces
  // are kept aside until every rename has succeeded, so that a rename that
  // still fails puts them back (before, it deleted the new files with the
  // old ones already gone; a review of that fix).
  for (const auto& f : files_) {
    std::error_code ec;
    if (std::filesystem::is_directory(f.path, ec)) {
      const std::string name = f.path.string();
      discard();
      throw InputError(name + ": cannot replace (a directory has its name); no files written");
    }
  }
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> aside;  // (result, its earlier version)
  std::vector<std::filesystem::path> renamed;
  const auto undo = [&](const std::string& name, const std::string& why) {
    for (const auto& r : renamed) {
      std::error_code ec;
      std::filesystem::remove(r, ec);
    }
    for (const auto& [path, old] : aside) {
      std::error_code ec;
      std::filesystem::rename(old, path, ec);
    }
    discard();  // the temporaries not yet renamed
    throw InputError(name + ": cannot replace (" + why + "); no files written");
  };
  for (const auto& f : files_) {
    std::error_code ec;
    if (!std::filesystem::exists(f.path, ec)) continue;
    const std::filesystem::path old = f.path.string() + ".replaced";
    std::filesystem::rename(f.path, old, ec);
    if (ec) undo(f.path.string(), ec.message());
    aside.push_back({f.path, old});
  }
  std::vector<std::string> written;
  for (const auto& f : files_) {
    std::error_code ec;
    std::filesystem::rename(f.tmp, f.path, ec);
    if (ec) undo(f.path.string(), ec.message());
    renamed.push_back(f.path);
    written.push_back(f.path.string());
  }
  for (const auto& [path, old] : aside) {
    std::error_code ec;
    std::filesystem::remove(old, ec);
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

}  // namespace cms::io
