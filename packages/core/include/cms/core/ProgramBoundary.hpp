// A program's error boundary (doc/architecture.md, "Errors"): exceptions
// carry context and are caught once, in main, turned into one message on
// rank 0 and a distinct exit code: bad input 2, numerical breakdown 3,
// anything else 5 (a bug). The drivers (drivers/DriverBoundary.hpp adds the
// solve statuses) and the examples, built against the installed library,
// share it.
#pragma once

#include <exception>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>

#include "cms/core/Error.hpp"

namespace cms {

/// The one table of outcomes (doc/user-guide.md, "Exit codes"): what a run
/// ended with, its exit code and the message printed for it. Only
/// ExitSuccess writes result files.
struct Outcome {
  int code;
  const char* message;
};
inline constexpr Outcome kSuccess{ExitSuccess, "success"};
inline constexpr Outcome kBadInput{ExitInputError, "bad input"};
inline constexpr Outcome kBreakdown{ExitNumericalError, "numerical breakdown"};
inline constexpr Outcome kNotConverged{ExitNotConverged, "not converged"};
inline constexpr Outcome kInternal{ExitInternalError, "internal error (please report)"};

/// A message without the Teuchos throw trace (file:line, "Throw number",
/// "Throw test ..." lines): one line for the console.
inline std::string condense(const std::string& reason) {
  std::istringstream in(reason);
  std::string line, out;
  static const std::regex where(R"(\s*\S+\.[ch]pp:\d+:\s*$)");
  while (std::getline(in, line)) {
    if (line.rfind("Throw number", 0) == 0 || line.rfind("Throw test", 0) == 0) continue;
    line = std::regex_replace(line, where, "");
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    out += (out.empty() || out.back() == ' ' ? "" : " ") + line;
  }
  return out;
}

/// Runs `body` (which returns the exit code) and maps cms::InputError,
/// cms::NumericalError and any other exception to their exit codes, with a
/// message on `root` naming `program`.
template <class Body>
int reportErrors(const char* program, bool root, Body&& body) {
  try {
    return body();
  } catch (const InputError& e) {
    if (root) std::cerr << program << ": " << kBadInput.message << ": " << e.what() << '\n';
    return kBadInput.code;
  } catch (const NumericalError& e) {
    if (root) std::cerr << program << ": " << kBreakdown.message << ": " << condense(e.what()) << '\n';
    return kBreakdown.code;
  } catch (const std::exception& e) {
    if (root) std::cerr << program << ": " << kInternal.message << ": " << condense(e.what()) << '\n';
    return kInternal.code;
  }
}

}  // namespace cms
