#include "render/worker_pool.h"

#include <algorithm>

namespace pt {

WorkerPool::WorkerPool(int threads) {
  int n = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
  for (int i = 1; i < n; ++i) workers_.emplace_back([this, i] { worker_main(i); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  workers_.clear();  // joins
}

void WorkerPool::run_tasks(int slot) {
  for (;;) {
    uint32_t index;
    {
      std::lock_guard lock(mutex_);
      if (next_ >= task_count_) return;
      index = next_++;
    }
    (*task_)(index, slot);
  }
}

void WorkerPool::worker_main(int slot) {
  uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || generation_ != seen; });
      if (stopping_) return;
      seen = generation_;
      ++active_;
    }
    run_tasks(slot);
    {
      std::lock_guard lock(mutex_);
      --active_;
    }
    done_.notify_all();
  }
}

void WorkerPool::parallel_for(uint32_t count, const std::function<void(uint32_t, int)>& task) {
  {
    std::lock_guard lock(mutex_);
    task_ = &task;
    task_count_ = count;
    next_ = 0;
    ++generation_;
  }
  wake_.notify_all();
  run_tasks(0);
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return next_ >= task_count_ && active_ == 0; });
  task_ = nullptr;
}

}  // namespace pt
