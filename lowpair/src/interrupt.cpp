#include "lowpair/interrupt.hpp"

#include <atomic>

namespace lowpair {

namespace {
std::atomic<InterruptCheck> installed{nullptr};
}  // namespace

InterruptCheck setInterruptCheck(InterruptCheck check) { return installed.exchange(check); }

void pollInterrupt() {
  const InterruptCheck check = installed.load(std::memory_order_relaxed);
  if (check != nullptr && check()) throw Interrupted();
}

}  // namespace lowpair
