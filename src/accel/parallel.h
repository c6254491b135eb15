#pragma once
/// The build's one parallel loop shape: a range cut into a few contiguous chunks, one per thread.
#include <algorithm>
#include <cstdint>
#include <thread>
#include <vector>

namespace pt {

/// Resolves BvhBuildOptions::threads: 0 means all hardware threads.
inline int build_threads(int requested) {
  return requested > 0 ? requested : int(std::max(1u, std::thread::hardware_concurrency()));
}

/// How many chunks parallel_chunks makes of n items.
inline int parallel_chunk_count(size_t n, int threads, size_t min_chunk) {
  return int(std::max<size_t>(1, std::min<size_t>(size_t(std::max(1, threads)), n / std::max<size_t>(1, min_chunk))));
}

/// Runs fn(chunk, begin, end) over [0, n) in up to `threads` contiguous chunks of at least `min_chunk` items, the
/// caller taking chunk 0. Chunk boundaries depend on n and the chunk count only.
template <class Fn>
void parallel_chunks(size_t n, int threads, size_t min_chunk, Fn&& fn) {
  const int chunks = parallel_chunk_count(n, threads, min_chunk);
  auto bound = [&](int c) { return n * size_t(c) / size_t(chunks); };
  std::vector<std::thread> helpers;
  for (int c = 1; c < chunks; ++c) helpers.emplace_back([&, c] { fn(c, bound(c), bound(c + 1)); });
  fn(0, size_t(0), bound(1));
  for (std::thread& h : helpers) h.join();
}

}  // namespace pt
