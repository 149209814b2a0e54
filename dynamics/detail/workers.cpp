#include "dynamics/detail/workers.hpp"

#include <chrono>

namespace grip::detail {

namespace {
using Clock = std::chrono::steady_clock;
constexpr auto kSpin = std::chrono::microseconds(200);  // a helper's wait before it sleeps
// How long a wait only spins before it also yields its vCPU each round: with more busy threads
// than vCPUs (another process stepping too), a thread that spun without yielding kept the one
// it waited for off the vCPU: a 1000-box pile on two threads took 13.9-19.1 ms a step beside a
// second process instead of 3.3 ms alone (11.7-13.4 with the yield).
constexpr auto kSpinAlone = std::chrono::microseconds(20);

inline void pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// One round of a wait that began at `began`: a pause, and past kSpinAlone a yield too (the
// clock is read every 64 rounds).
inline void waitRound(int round, Clock::time_point began, bool& yielding) {
  pause();
  if (!yielding && round % 64 == 0) yielding = Clock::now() - began > kSpinAlone;
  if (yielding) std::this_thread::yield();
}
}  // namespace

Workers::Workers(int threads)
    : claimed_(std::make_unique<std::atomic<bool>[]>(static_cast<size_t>(threads))) {
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
  unsigned seen = 0;
  for (;;) {
    unsigned now = posted_.load(std::memory_order_acquire);
    const Clock::time_point began = Clock::now(), until = began + kSpin;
    bool yielding = false;
    for (int spins = 1; now == seen; now = posted_.load(std::memory_order_acquire), ++spins) {
      waitRound(spins, began, yielding);
      if (spins % 64 == 0 && Clock::now() > until) posted_.wait(seen, std::memory_order_acquire);
    }
    seen = now;
    if (stopping_.load()) return;
    runUnlessTaken(index);
  }
}

void Workers::runUnlessTaken(int t) {
  if (claimed_[t].exchange(true, std::memory_order_acq_rel)) return;  // taken already
  guarded(t);
  busy_.fetch_sub(1, std::memory_order_release);
}

void Workers::start(const std::function<void(int)>& task) {
  task_ = &task;
  error_ = nullptr;
  busy_.store(static_cast<int>(helpers_.size()), std::memory_order_relaxed);
  // (Release: a helper that claims a task of this job without having seen it posted, late from
  // the one before, must see this job's task_.)
  for (size_t i = 1; i <= helpers_.size(); ++i) claimed_[i].store(false, std::memory_order_release);
  posted_.fetch_add(1, std::memory_order_release);
  posted_.notify_all();
}

void Workers::finish() {
  const Clock::time_point began = Clock::now();
  bool yielding = false;
  for (int round = 1; busy_.load(std::memory_order_acquire) != 0; ++round)
    waitRound(round, began, yielding);
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
  // A helper's share it has not taken yet (asleep, or off its vCPU while another process runs)
  // is the calling thread's now, rather than a wait of up to a scheduler slice: beside a second
  // process stepping, a 1000-box pile took 11.7-13.4 ms a step on two threads without this, 5.7
  // with it (8.1 on one thread).
  for (int i = 1; i <= static_cast<int>(helpers_.size()); ++i) runUnlessTaken(i);
  finish();
}

}  // namespace grip::detail
