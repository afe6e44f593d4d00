#pragma once
// A library call rejected with std::invalid_argument and exactly this message (the size checks of the
// public API: kinematics_test.cpp, jacobian_test.cpp).
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace lowpair_test {

template <class Call>
void expectInvalid(const Call& call, const std::string& message) {
  try {
    call();
    ADD_FAILURE() << "no exception; expected \"" << message << "\"";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

}  // namespace lowpair_test
