// Assert that a call throws cms::InputError whose message contains a given
// piece (the key, file, line or tag the user must be told about).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "cms/core/Error.hpp"

namespace cms::fixtures {

template <class F>
void expectInputError(F f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no cms::InputError (expected one mentioning \"" << needle << "\")";
  } catch (const cms::InputError& err) {
    EXPECT_NE(std::string(err.what()).find(needle), std::string::npos) << err.what();
  }
}

}  // namespace cms::fixtures
