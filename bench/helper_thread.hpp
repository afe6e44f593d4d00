#pragma once
// One persistent helper thread for the two-thread batch benchmark: the caller publishes a job by bumping
// a generation counter, runs its own half, then spins until the helper reports its half done. Created
// outside the timed loop; the helper spins (then yields) only while the benchmark that owns it runs.
#include <atomic>
#include <thread>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define LOWPAIR_BENCH_PAUSE() _mm_pause()
#else
#define LOWPAIR_BENCH_PAUSE() std::this_thread::yield()
#endif

namespace lowpair_bench {

class HelperThread {
 public:
  using Job = void (*)(void* context, int part);  // part 0: caller, part 1: helper

  HelperThread() : worker_([this] { loop(); }) {}
  ~HelperThread() {
    stop_.store(true, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
    worker_.join();
  }
  HelperThread(const HelperThread&) = delete;
  HelperThread& operator=(const HelperThread&) = delete;

  void run(Job job, void* context) {
    job_ = job;
    context_ = context;
    done_.store(false, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
    job(context, 0);
    // spin briefly, then yield: on a loaded 2-core machine the helper may be waiting for this core
    for (int spins = 0; !done_.load(std::memory_order_acquire); ++spins) {
      if (spins < 4096) {
        LOWPAIR_BENCH_PAUSE();
      } else {
        std::this_thread::yield();
      }
    }
  }

 private:
  void loop() {
    unsigned long seen = 0;
    for (;;) {
      unsigned long g;
      int spins = 0;
      while ((g = generation_.load(std::memory_order_acquire)) == seen) {
        if (++spins < (1 << 16)) {
          LOWPAIR_BENCH_PAUSE();
        } else {
          std::this_thread::yield();
        }
      }
      seen = g;
      if (stop_.load(std::memory_order_relaxed)) return;
      job_(context_, 1);
      done_.store(true, std::memory_order_release);
    }
  }

  std::atomic<unsigned long> generation_{0};
  std::atomic<bool> done_{true};
  std::atomic<bool> stop_{false};
  Job job_ = nullptr;
  void* context_ = nullptr;
  std::thread worker_;
};

}  // namespace lowpair_bench
