#pragma once
/// @file check.hpp
/// Error tiers (STYLE.md): `LP_ASSERT` internal invariant (debug only), `LP_CHECK` user input at the API
/// boundary (throws std::invalid_argument, in every build type). Numerical conditions are returned as
/// data, never thrown.
///
/// Internal to the library: no public header includes it and it is not installed. The checks of the hot
/// paths (forwardKinematics, computeJacobians, the Jacobian getters) are a few integer compares behind
/// LP_UNLIKELY; their message is built only on failure, in an LP_COLD function, so the success path
/// allocates nothing (tests/lib/alloc_test.cpp).

#include <cassert>
#include <sstream>
#include <stdexcept>
#include <string>

// LP_UNLIKELY: the branch a check fails on; LP_COLD: a function that builds and throws a check's message,
// kept out of line so that the checked function's fast path carries no string code.
#if defined(__GNUC__) || defined(__clang__)
#define LP_UNLIKELY(cond) __builtin_expect(static_cast<bool>(cond), 0)
#define LP_COLD __attribute__((noinline, cold))
#else
#define LP_UNLIKELY(cond) static_cast<bool>(cond)
#define LP_COLD
#endif

#define LP_ASSERT(cond) assert(cond)

#define LP_CHECK(cond, message)                            \
  do {                                                     \
    if (LP_UNLIKELY(!(cond))) {                            \
      std::ostringstream lp_check_stream_;                 \
      lp_check_stream_ << message;                         \
      throw std::invalid_argument(lp_check_stream_.str()); \
    }                                                      \
  } while (false)

namespace lowpair::detail {
/// "1 joint", "6 joints": a count and its noun, for check messages.
inline std::string counted(long long n, const char* noun) { return std::to_string(n) + " " + noun + (n == 1 ? "" : "s"); }
}  // namespace lowpair::detail
