#pragma once
/// A fixed pool of worker threads that runs parallel-for jobs over task indices (tiles). The caller thread joins
/// in, and waits for the job to end. Threads live as long as the pool: no thread is created per frame.
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace pt {

class WorkerPool {
 public:
  /// `threads` workers in total including the calling thread; 0 = hardware concurrency.
  explicit WorkerPool(int threads = 0);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int thread_count() const { return int(workers_.size()) + 1; }
  /// Calls task(index, thread_slot) for every index in [0, count), spread over the threads; returns when all are
  /// done. thread_slot in [0, thread_count()) identifies per-thread scratch.
  void parallel_for(uint32_t count, const std::function<void(uint32_t, int)>& task);

 private:
  void worker_main(int slot);
  void run_tasks(int slot);

  std::vector<std::jthread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  const std::function<void(uint32_t, int)>* task_ = nullptr;
  uint32_t task_count_ = 0;
  uint32_t next_ = 0;
  int active_ = 0;
  uint64_t generation_ = 0;
  bool stopping_ = false;
};

}  // namespace pt
