// The drivers' error boundary (DEVELOPERS.md: exceptions carry context and
// are caught at the driver, turned into one message and a distinct exit
// code): bad input 2, numerical breakdown 3, anything else 5 (a bug).
#pragma once

#include <exception>
#include <iostream>

#include "cms/core/Error.hpp"

namespace cms::drivers {

/// Runs `body` (which returns the exit code) and maps cms::InputError,
/// cms::NumericalError and any other exception to their exit codes, with a
/// message on `root` naming `program`.
template <class Body>
int reportErrors(const char* program, bool root, Body&& body) {
  try {
    return body();
  } catch (const InputError& e) {
    if (root) std::cerr << program << ": bad input: " << e.what() << '\n';
    return ExitInputError;
  } catch (const NumericalError& e) {
    if (root) std::cerr << program << ": numerical breakdown: " << e.what() << '\n';
    return ExitNumericalError;
  } catch (const std::exception& e) {
    if (root) std::cerr << program << ": internal error (please report): " << e.what() << '\n';
    return ExitInternalError;
  }
}

}  // namespace cms::drivers
