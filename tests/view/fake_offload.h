#pragma once
// Rank 0's side of the viewer offload without MPI, shared by the offload and panel tests: a channel whose workers'
// results the test writes itself, and the films those results carry.
#include <utility>
#include <vector>

#include "dist/cluster.h"
#include "render/film.h"

namespace pt::test {

/// What rank 0 posted and what the "workers" sent; outlives the channel (the root owns and destroys it).
struct Wire {
  std::vector<std::vector<uint8_t>> posted, results;
};

struct FakeChannel final : OffloadChannel {
  Wire* wire;
  explicit FakeChannel(Wire* w) : wire(w) {}
  void post(std::vector<uint8_t> m) override { wire->posted.push_back(std::move(m)); }
  std::vector<std::vector<uint8_t>> poll_results() override { return std::exchange(wire->results, {}); }
  void close() override { post({}); }
  std::vector<std::vector<uint8_t>> poll_posts() override { return {}; }
  bool send_result(std::vector<uint8_t>) override { return false; }
  void finish() override {}
};

/// A worker film of w x h pixels: `n` samples of `c` in every pixel.
inline Film worker_film(vec3 c, int n, int w = 8, int h = 8) {
  Film f(w, h);
  for (size_t p = 0; p < f.pixel_count(); ++p)
    for (int i = 0; i < n; ++i) f.add(p, c, uint64_t(i));
  return f;
}

}  // namespace pt::test
