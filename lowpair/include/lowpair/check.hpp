#pragma once
/// @file check.hpp
/// Error tiers (STYLE.md): `LP_ASSERT` internal invariant (debug only), `LP_CHECK` user input at the API
/// boundary (throws std::invalid_argument). Numerical conditions are returned as data, never thrown.

#include <cassert>
#include <sstream>
#include <stdexcept>
#include <string>

#define LP_ASSERT(cond) assert(cond)

#define LP_CHECK(cond, message)                        \
  do {                                                 \
    if (!(cond)) {                                     \
      std::ostringstream lp_check_stream_;             \
      lp_check_stream_ << message;                     \
      throw std::invalid_argument(lp_check_stream_.str()); \
    }                                                  \
  } while (false)
