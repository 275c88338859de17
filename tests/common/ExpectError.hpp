// Assert that a call throws cms::InputError whose message contains a given
// piece (the key, file, line or tag the user must be told about).
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <initializer_list>
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

/// fn throws cms::InputError whose message holds every one of `parts`.
inline void expectInputErrorWith(const std::function<void()>& fn, std::initializer_list<std::string> parts) {
  try {
    fn();
    ADD_FAILURE() << "no cms::InputError (expected one mentioning \"" << *parts.begin() << "\")";
  } catch (const cms::InputError& e) {
    const std::string what = e.what();
    for (const std::string& p : parts)
      EXPECT_NE(what.find(p), std::string::npos) << "message \"" << what << "\" lacks \"" << p << "\"";
  }
}

}  // namespace cms::fixtures
