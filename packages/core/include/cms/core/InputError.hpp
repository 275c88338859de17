// cms::InputError and CMS_INPUT_CHECK alone, without Teuchos: for code
// built apart from Trilinos (the Gmsh reader module of packages/mesh, loaded
// only when a Gmsh mesh is read). Everything else includes Error.hpp.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace cms {

/// A user's input is malformed: wrong size, wrong sign, NaN, unknown key.
class InputError : public std::invalid_argument {
public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace cms

/// Throw cms::InputError with the streamed message when cond holds. Unlike
/// TEUCHOS_TEST_FOR_EXCEPTION it adds no source location: the message is for
/// the user, and must itself name the object, key or file and what is wrong.
#define CMS_INPUT_CHECK(cond, msg)            \
  do {                                        \
    if (cond) {                               \
      std::ostringstream cms_input_check_os_; \
      cms_input_check_os_ << msg;             \
      throw ::cms::InputError(cms_input_check_os_.str()); \
    }                                         \
  } while (0)
