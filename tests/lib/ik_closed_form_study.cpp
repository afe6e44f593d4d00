// The run behind docs/ik.md's claim (label `study`, `make study`): on the PUMA 560, the Stanford arm and
// the UR5e, 10,000 random targets each: every closed-form solution exact to 1e-12 L through FK without
// refinement, the target's own configuration among them, and every solution the numerical solver reaches from 16
// random seeds per target one of them (ik_closed_form_helpers.hpp). ik_closed_form_test.cpp runs 150 targets.
#include <gtest/gtest.h>

#include "ik_closed_form_helpers.hpp"

namespace {

using namespace ik_closed_form_helpers;

TEST(ClosedFormStudy, EverySolutionOf10000PumaTargets) { everySolutionFound(puma(), 10000, 16, 8); }
TEST(ClosedFormStudy, EverySolutionOf10000StanfordTargets) { everySolutionFound(stanford(), 10000, 16, 8); }
TEST(ClosedFormStudy, EverySolutionOf10000Ur5eTargets) { everySolutionFound(ur5e(), 10000, 16, 8); }

}  // namespace
