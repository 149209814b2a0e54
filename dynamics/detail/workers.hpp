// A small pool of worker threads for the step's two regions (their narrowphase and their
// solve). Each thread gets its own share and writes only its own output, and one thread runs
// the shares one after the other in the same order, so the result does not depend on how many
// threads there are: a run with 2 threads is bit-identical to a run with 1.
#pragma once

#include <atomic>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace grip::detail {

class Workers {
 public:
  explicit Workers(int threads);  // threads in all, the calling thread included
  ~Workers();
  Workers(const Workers&) = delete;
  Workers& operator=(const Workers&) = delete;

  int threads() const { return static_cast<int>(helpers_.size()) + 1; }
  // Runs task(t) for every t in [0, threads()) and returns when all have run: on thread t (the
  // calling thread being 0), so that a share given to the same thread step after step finds its
  // data in that thread's cache, unless thread t has not taken it by the time the calling
  // thread's own is done: then the calling thread runs it. An exception from a task is rethrown
  // here (the first one).
  void runEach(const std::function<void(int)>& task);

 private:
  void start(const std::function<void(int)>& task);
  void finish();
  void helperLoop(int index);
  void guarded(int arg);
  void runUnlessTaken(int t);  // task t, by whichever thread claims it first

  std::vector<std::thread> helpers_;
  // A step hands out a dozen jobs within a few milliseconds, so a helper spins a while after
  // each before it sleeps: waking a sleeping thread takes tens of microseconds on a VM.
  std::atomic<unsigned> posted_{0};  // bumped for every job
  std::atomic<int> busy_{0};         // helpers still inside the current job
  std::atomic<bool> stopping_{false};
  std::unique_ptr<std::atomic<bool>[]> claimed_;  // per thread: this job's task t is taken
  const std::function<void(int)>* task_ = nullptr;
  std::mutex errorMutex_;
  std::exception_ptr error_;
};

}  // namespace grip::detail
