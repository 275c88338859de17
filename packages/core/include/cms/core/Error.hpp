// Exception types and process exit codes shared by every layer.
//
// Bad input (a user's matrix, file or parameter) throws InputError with a
// message naming the object, key and the valid range; a numerical breakdown
// that no fallback can absorb throws NumericalError. Numerical outcomes that a
// caller can act on (not converged, unstable) are statuses in results, never
// exceptions (doc/architecture.md, "Errors").
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

#include <Teuchos_TestForException.hpp>

#include "cms/core/InputError.hpp"

namespace cms {

/// A computation broke down in a way no fallback recovers from.
class NumericalError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Exit codes of every driver: distinct so scripts can tell failures apart.
enum ExitCode : int {
  ExitSuccess = 0,
  ExitInputError = 2,      ///< malformed input: nothing computed, nothing written
  ExitNumericalError = 3,  ///< a solve broke down
  ExitNotConverged = 4,    ///< ran, but some requested result did not converge
  ExitInternalError = 5    ///< a bug: please report
};

}  // namespace cms
