// A small pool of worker threads for the step's independent loops (narrowphase, contact
// preparation). Work is cut into numbered chunks and every chunk writes only its own
// output, so the result does not depend on which thread ran which chunk, nor on how many
// threads there are: a run with 2 threads is bit-identical to a run with 1.
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
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
  // Runs task(chunk) for every chunk in [0, chunks); returns when all have run. The calling
  // thread takes chunks too. An exception from a task is rethrown here (the first one).
  void run(int chunks, const std::function<void(int)>& task);

 private:
  void helperLoop();
  void takeChunks();

  std::vector<std::thread> helpers_;
  std::mutex mutex_;
  std::condition_variable wake_, finished_;
  const std::function<void(int)>* task_ = nullptr;
  int chunks_ = 0;
  std::atomic<int> next_{0};
  int busy_ = 0;             // helpers still inside the current job
  unsigned generation_ = 0;  // bumped for every job
  bool stopping_ = false;
  std::exception_ptr error_;
};

}  // namespace grip::detail
