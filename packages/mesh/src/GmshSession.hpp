// Gmsh SDK session and its first error: shared by the Gmsh reader module
// (GmshReader.cpp) and the .geo mesher helper (GeoMesher.cpp).
#pragma once

#include <string>
#include <vector>

#include <gmsh.h>

namespace cms::mesh::detail {

/// Gmsh's SDK is one global state: initialise it for one read (which resets
/// every option a previous read set) and always finalise it, also when the
/// read throws. The ONELAB parameters survive finalize(): without clearing
/// them, a script's DefineConstant takes the value a previous script gave a
/// parameter of the same name instead of its own default. (Each
/// initialize/finalize pair leaks a little in Gmsh 4.8, growing with the
/// number of pairs: ~55 MB after 2000 reads; nothing for the handful of
/// reads of a normal run. .geo scripts are run in a process of their own:
/// see GeoMesher.cpp.)
class GmshSession {
public:
  explicit GmshSession(bool terminal = false) {
    gmsh::initialize(0, nullptr, false);  // no gmshrc / gmsh-options from the user's home
    active_ = true;
    gmsh::option::setNumber("General.Terminal", terminal ? 1 : 0);
    gmsh::logger::start();  // for the first error of a script (see firstError)
    gmsh::onelab::clear();
    // MSH 2 periodic links are not read (the Mesh has no use for them, and
    // the structure scan does not validate them): Gmsh's default, made explicit.
    gmsh::option::setNumber("Mesh.IgnorePeriodicity", 1);
  }
  ~GmshSession() {
    if (!active_) return;
    try {
      gmsh::logger::stop();  // and clear: the log outlives finalize()
      gmsh::onelab::clear();
      gmsh::finalize();
    } catch (...) {
    }
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

private:
  bool active_ = false;
};

/// The errors Gmsh logged in this session, in order, without their "Error"
/// tag.
inline std::vector<std::string> loggedErrors() {
  std::vector<std::string> log, errors;
  try {
    gmsh::logger::get(log);
  } catch (...) {
    return errors;
  }
  for (const auto& l : log)
    if (l.compare(0, 5, "Error") == 0) {
      const std::size_t colon = l.find(':');
      if (colon == std::string::npos) {
        errors.push_back(l);
        continue;
      }
      const std::size_t text = l.find_first_not_of(' ', colon + 1);
      errors.push_back(text == std::string::npos ? std::string() : l.substr(text));
    }
  return errors;
}

/// The first error Gmsh logged in this session: a script's parser goes on
/// after a syntax error, and its last message (what it throws) is often
/// "line 0: syntax error" at the end of the file.
inline std::string firstError() {
  const std::vector<std::string> errors = loggedErrors();
  return errors.empty() ? std::string() : errors.front();
}

}  // namespace cms::mesh::detail
