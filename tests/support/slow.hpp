// How much slower this build runs the tests: INHAP_TEST_SLOW from ctest (3 under the sanitizers,
// see tests/CMakeLists.txt), 1 when unset or not a number from 1 to 100. A test stretches its
// own waits by it, as its ctest time-out is.
#pragma once

#include <cstdlib>

namespace inhap::test {

inline double slow_factor() {
  const char* s = std::getenv("INHAP_TEST_SLOW");
  const double f = s ? std::atof(s) : 1.0;
  return f >= 1.0 && f <= 100.0 ? f : 1.0;
}

}  // namespace inhap::test
