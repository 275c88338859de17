// The drivers' boundary (cms/core/ProgramBoundary.hpp): each exception to
// its exit code, and a Teuchos exception's throw trace (file:line, "Throw
// number", "Throw test") condensed out of the one console line. The
// driver-level check of this used an Anasazi breakdown that a scene can no
// longer reach (the sparse solver's subspace now fits in the state space),
// so it is tested here on a Teuchos exception made for the purpose.
#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>
#include <string>

#include <Teuchos_Assert.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/ProgramBoundary.hpp"

namespace {

std::string teuchosMessage() {
  try {
    TEUCHOS_TEST_FOR_EXCEPTION(true, std::runtime_error, "Orthogonalization constraints not feasible");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ProgramBoundary, ATeuchosThrowTraceIsCondensedToItsMessage) {
  const std::string raw = teuchosMessage();
  ASSERT_NE(raw.find("Throw number"), std::string::npos) << raw;  // what Teuchos adds
  const std::string line = cms::condense(raw);
  EXPECT_EQ(line.find("Throw number"), std::string::npos) << line;
  EXPECT_EQ(line.find("Throw test"), std::string::npos) << line;
  EXPECT_EQ(line.find("ProgramBoundaryTest.cpp"), std::string::npos) << line;
  EXPECT_EQ(line.find('\n'), std::string::npos) << line;
  EXPECT_NE(line.find("Orthogonalization constraints not feasible"), std::string::npos) << line;
}

TEST(ProgramBoundary, EachExceptionHasItsExitCode) {
  EXPECT_EQ(cms::reportErrors("t", false, [] { return 0; }), 0);
  EXPECT_EQ(cms::reportErrors("t", false, []() -> int { throw cms::InputError("x"); }), cms::kBadInput.code);
  EXPECT_EQ(cms::reportErrors("t", false, []() -> int { throw cms::NumericalError("x"); }), cms::kBreakdown.code);
  EXPECT_EQ(cms::reportErrors("t", false, []() -> int { throw std::runtime_error("x"); }), cms::kInternal.code);
}
