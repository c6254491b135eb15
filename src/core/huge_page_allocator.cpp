#include "core/huge_page_allocator.h"

#include <deque>
#include <mutex>

namespace pt::huge_block_cache {
namespace {

struct Cache {
  std::mutex mutex;
  std::deque<std::pair<void*, size_t>> blocks;  ///< oldest first
  size_t bytes = 0;
};

/// Never destroyed: blocks stay reachable until exit (no leak report), and no allocator used during static
/// destruction finds the cache gone.
Cache& cache() {
  static Cache* c = new Cache;
  return *c;
}

}  // namespace

void* take(size_t bytes) {
  Cache& c = cache();
  std::lock_guard<std::mutex> lock(c.mutex);
  for (auto it = c.blocks.rbegin(); it != c.blocks.rend(); ++it) {  // newest first: most likely still in cache
    if (it->second != bytes) continue;
    void* p = it->first;
    c.bytes -= bytes;
    c.blocks.erase(std::next(it).base());
    return p;
  }
  return nullptr;
}

void give(void* p, size_t bytes) {
  if (!p) return;
  if (bytes > kMaxBytes) {
    std::free(p);
    return;
  }
  std::deque<void*> evicted;
  {
    Cache& c = cache();
    std::lock_guard<std::mutex> lock(c.mutex);
    c.blocks.emplace_back(p, bytes);
    c.bytes += bytes;
    while (c.bytes > kMaxBytes) {
      evicted.push_back(c.blocks.front().first);
      c.bytes -= c.blocks.front().second;
      c.blocks.pop_front();
    }
  }
  for (void* q : evicted) std::free(q);  // outside the lock
}

size_t held_bytes() {
  Cache& c = cache();
  std::lock_guard<std::mutex> lock(c.mutex);
  return c.bytes;
}

void release_all() {
  std::deque<std::pair<void*, size_t>> all;
  {
    Cache& c = cache();
    std::lock_guard<std::mutex> lock(c.mutex);
    all.swap(c.blocks);
    c.bytes = 0;
  }
  for (auto& [p, bytes] : all) std::free(p);
}

}  // namespace pt::huge_block_cache
