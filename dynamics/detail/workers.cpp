#include "dynamics/detail/workers.hpp"

#include <chrono>

namespace grip::detail {

namespace {
constexpr auto kSpin = std::chrono::microseconds(200);  // a helper's wait before it sleeps

inline void pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}
}  // namespace

Workers::Workers(int threads) {
  for (int i = 1; i < threads; ++i) helpers_.emplace_back([this, i] { helperLoop(i); });
}

Workers::~Workers() {
  stopping_.store(true);
  posted_.fetch_add(1);
  posted_.notify_all();
  for (std::thread& t : helpers_) t.join();
}

void Workers::guarded(int arg) {
  try {
    (*task_)(arg);
  } catch (...) {
    std::lock_guard<std::mutex> lock(errorMutex_);
    if (!error_) error_ = std::current_exception();
  }
}

void Workers::helperLoop(int index) {
  using Clock = std::chrono::steady_clock;
  unsigned seen = 0;
  for (;;) {
    unsigned now = posted_.load(std::memory_order_acquire);
    const Clock::time_point until = Clock::now() + kSpin;
    for (int spins = 1; now == seen; now = posted_.load(std::memory_order_acquire), ++spins) {
      pause();
      if (spins % 64 == 0 && Clock::now() > until) posted_.wait(seen, std::memory_order_acquire);
    }
    seen = now;
    if (stopping_.load()) return;
    guarded(index);
    busy_.fetch_sub(1, std::memory_order_release);
  }
}

void Workers::start(const std::function<void(int)>& task) {
  task_ = &task;
  error_ = nullptr;
  busy_.store(static_cast<int>(helpers_.size()), std::memory_order_relaxed);
  posted_.fetch_add(1, std::memory_order_release);
  posted_.notify_all();
}

void Workers::finish() {
  while (busy_.load(std::memory_order_acquire) != 0) pause();
  task_ = nullptr;
  if (error_) std::rethrow_exception(error_);
}

void Workers::runEach(const std::function<void(int)>& task) {
  if (helpers_.empty()) {
    task(0);
    return;
  }
  start(task);
  guarded(0);
  finish();
}

}  // namespace grip::detail
