/// Binned SAH BVH construction (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies";
/// pbrt-v4 section 7.3.2), with the top levels built in parallel.
///
/// Speed comes from three habits of fast builders (Embree, madmann91/bvh): the primitive references are one
/// contiguous array that is partitioned in place, so every pass reads memory in order; one pass bins all three
/// axes; and the partition collects both children's box and centroid bounds as it goes, so no node needs a
/// separate bounds pass.
#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>

#include "accel/bvh.h"
#include "accel/parallel.h"

namespace pt {
namespace {

constexpr int kMaxBins = 64;
/// Below this depth the SAH decides; beyond it splits are median splits so the depth stays bounded.
constexpr int kSahDepthLimit = kBvhMaxDepth - 32;
/// Subtrees of at least this many primitives are built as jobs of their own, which any build thread may take.
constexpr uint32_t kMinParallelPrims = 4096;
/// A root of at least this many primitives is split by all build threads together (Builder::split_root).
constexpr uint32_t kMinChunkedRootPrims = 4 * kMinParallelPrims;

/// A box as two SSE registers (the w lanes are ignored): one min and one max per extend.
struct Box4 {
  __m128 lo = _mm_set1_ps(kInfinity), hi = _mm_set1_ps(-kInfinity);
  void extend(const Box4& b) { extend(b.lo, b.hi); }
  void extend(__m128 l, __m128 h) { lo = _mm_min_ps(lo, l); hi = _mm_max_ps(hi, h); }
  void extend_point(__m128 p) { lo = _mm_min_ps(lo, p); hi = _mm_max_ps(hi, p); }
  float half_area() const {
    alignas(16) float e[4];
    _mm_store_ps(e, _mm_max_ps(_mm_sub_ps(hi, lo), _mm_setzero_ps()));
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
  }
  AABB aabb() const {
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    return {vec3(l[0], l[1], l[2]), vec3(h[0], h[1], h[2])};
  }
};

/// A primitive reference, 32 bytes (as Embree's): its box, with the primitive id in the w lane of the low corner.
/// Its centroid is the box center, kept doubled (lo + hi: binning only needs relative positions, and the factor 2 is
/// exact), so a reference is half the size it would be with a centroid and an id of its own: every level of the
/// build reads and partitions half the bytes.
/// Trivially constructible, so the array is made without a serial pass of constructors: the threads that fill it
/// touch its pages first.
struct alignas(32) PrimRef {
  __m128 lo, hi;
  uint32_t id() const { return uint32_t(_mm_cvtsi128_si32(_mm_shuffle_epi32(_mm_castps_si128(lo), 3))); }
  /// lo + hi (w lane 0), or 0 where that is not finite (an empty box of a non-finite primitive), so no NaN reaches
  /// the bins or the median's order.
  __m128 center2() const {
    const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
    const __m128 c = _mm_add_ps(_mm_and_ps(lo, xyz), _mm_and_ps(hi, xyz));
    const __m128 finite = _mm_cmplt_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), c), _mm_set1_ps(kInfinity));
    return _mm_and_ps(c, finite);
  }
  float center_axis(int a) const {
    alignas(16) float c[4];
    _mm_store_ps(c, center2());
    return c[a];
  }
  void set(const AABB& b, uint32_t prim) {
    const AABB f = finite_or_empty(b);
    lo = _mm_castsi128_ps(_mm_setr_epi32(std::bit_cast<int32_t>(f.lo.x), std::bit_cast<int32_t>(f.lo.y),
                                             std::bit_cast<int32_t>(f.lo.z), int32_t(prim)));
    hi = _mm_setr_ps(f.hi.x, f.hi.y, f.hi.z, 0.0f);
  }
};
static_assert(sizeof(PrimRef) == 32 && std::is_trivially_default_constructible_v<PrimRef>);

/// Bounds of a set of references and of their centroids.
struct RangeBounds {
  Box4 box, centroids;
  void extend(const PrimRef& r) { extend(r, r.center2()); }
  void extend(const PrimRef& r, __m128 center2) { box.extend(r.lo, r.hi); centroids.extend_point(center2); }
  void extend(const RangeBounds& o) { box.extend(o.box); centroids.extend(o.centroids); }
};

struct Bin {
  Box4 box;
  uint32_t count = 0;
};

struct Split {
  int axis = -1;
  int bin = 0;  ///< primitives in bins [0, bin] go left
  float cost = kInfinity;
};

struct Builder {
  std::span<PrimRef> refs;
  const BvhBuildOptions& options;
  int max_bins;
  uint32_t max_leaf;
  uint32_t block_mask;  ///< leaf block size - 1 when that is a power of two (as it always is), else 0
  std::atomic<int> depth{0};
  int threads = 1;  ///< build threads (set by build)

  Builder(std::span<PrimRef> r, const BvhBuildOptions& o)
      : refs(r),
        options(o),
        max_bins(std::clamp(o.bins, 2, kMaxBins)),
        max_leaf(uint32_t(std::max(1, o.max_leaf_size))) {
    const uint32_t block = uint32_t(sah_leaf_tests(1, o));
    block_mask = std::has_single_bit(block) ? block - 1 : 0;
  }

  struct Task {
    uint32_t node, begin, end;
    int depth;
    RangeBounds bounds;
  };

  /// sah_leaf_tests, without its integer division when the block size is a power of two (the bin sweeps call this
  /// for every bin: the division was 3% of the build).
  float blocks(uint32_t count) const {
    return block_mask ? float((count + block_mask) & ~block_mask) : sah_leaf_tests(count, options);
  }

  /// Small nodes get fewer bins: with as many bins as primitives the binned split is already close to a sweep.
  int bins_for(uint32_t count) const { return std::clamp(int(count), std::min(8, max_bins), max_bins); }

  /// Bin index of every reference on all three axes at once.
  struct Binning {
    __m128 lo, scale;
    int bins;
    __m128i index(const PrimRef& r) const { return index_of(r.center2()); }
    __m128i index_of(__m128 center2) const {
      const __m128 f = _mm_mul_ps(_mm_sub_ps(center2, lo), scale);  // clamped before the conversion; NaN -> 0
      return _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), _mm_set1_ps(float(bins - 1))));
    }
  };

  Binning make_binning(const Task& t) const {
    const int bins = bins_for(t.end - t.begin);
    const __m128 extent = _mm_sub_ps(t.bounds.centroids.hi, t.bounds.centroids.lo);
    // scale = bins / extent where extent > 0, else 0 (everything in bin 0)
    const __m128 positive = _mm_cmpgt_ps(extent, _mm_setzero_ps());
    const __m128 scale = _mm_and_ps(positive, _mm_div_ps(_mm_set1_ps(float(bins)), extent));
    return {t.bounds.centroids.lo, scale, bins};
  }

  /// Clears the bins, then bins the references [begin, end) on all three axes.
  void bin_range(uint32_t begin, uint32_t end, const Binning& binning, Bin (*bins)[kMaxBins]) const {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < binning.bins; ++b) bins[a][b] = Bin{};
    for (uint32_t i = begin; i < end; ++i) {
      const PrimRef& r = refs[i];
      alignas(16) int32_t idx[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(idx), binning.index(r));
      for (int a = 0; a < 3; ++a) {
        Bin& b = bins[a][idx[a]];
        b.box.extend(r.lo, r.hi);
        b.count++;
      }
    }
  }

  Split find_split(const Task& t, const Binning& binning, Bin (*bins)[kMaxBins]) const {
    const int n_bins = binning.bins;
    bin_range(t.begin, t.end, binning, bins);
    const uint32_t count = t.end - t.begin;
    return sweep(bins, n_bins, count, _mm_sub_ps(t.bounds.centroids.hi, t.bounds.centroids.lo));
  }

  /// Half the surface area of three boxes at once, one per lane (the w lane is 0): the extents are transposed so
  /// that lane a holds box a's x, y and z extents in three registers. Empty boxes (hi < lo) have area 0.
  static __m128 half_areas(const Box4& x, const Box4& y, const Box4& z) {
    __m128 ex = _mm_max_ps(_mm_sub_ps(x.hi, x.lo), _mm_setzero_ps());
    __m128 ey = _mm_max_ps(_mm_sub_ps(y.hi, y.lo), _mm_setzero_ps());
    __m128 ez = _mm_max_ps(_mm_sub_ps(z.hi, z.lo), _mm_setzero_ps());
    __m128 ew = _mm_setzero_ps();
    _MM_TRANSPOSE4_PS(ex, ey, ez, ew);  // now ex = the three boxes' x extents, ey their y, ez their z
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(ex, ey), _mm_mul_ps(ey, ez)), _mm_mul_ps(ez, ex));
  }

  /// blocks() of four counts.
  __m128 blocks4(__m128i n) const {
    if (block_mask || options.leaf_block_size <= 1) {
      const __m128i mask = _mm_set1_epi32(int(block_mask));
      return _mm_cvtepi32_ps(_mm_andnot_si128(mask, _mm_add_epi32(n, mask)));
    }
    alignas(16) uint32_t c[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(c), n);
    return _mm_setr_ps(blocks(c[0]), blocks(c[1]), blocks(c[2]), blocks(c[3]));
  }

  /// The SAH sweep over the bins of the three axes at once, one axis per SSE lane (as Embree's BinInfo::best):
  /// from the right to get the cost of every right side, then from the left. A split needs primitives on both
  /// sides and an axis whose centroid extent is positive. Ties go to the lowest bin, then the lowest axis.
  Split sweep(const Bin (*bins)[kMaxBins], int n_bins, uint32_t count, __m128 centroid_extent) const {
    auto counts = [&](int b) {
      return _mm_setr_epi32(int(bins[0][b].count), int(bins[1][b].count), int(bins[2][b].count), 0);
    };
    alignas(16) __m128 right_cost[kMaxBins];
    Box4 ax, ay, az;
    __m128i n = _mm_setzero_si128();
    for (int b = n_bins - 1; b > 0; --b) {
      ax.extend(bins[0][b].box);
      ay.extend(bins[1][b].box);
      az.extend(bins[2][b].box);
      n = _mm_add_epi32(n, counts(b));
      right_cost[b - 1] = _mm_mul_ps(half_areas(ax, ay, az), blocks4(n));
    }
    ax = ay = az = Box4{};
    n = _mm_setzero_si128();
    const __m128i total = _mm_set1_epi32(int(count));
    const __m128i axes = _mm_castps_si128(_mm_cmpgt_ps(centroid_extent, _mm_setzero_ps()));
    const __m128i xyz = _mm_setr_epi32(-1, -1, -1, 0);
    __m128 best_cost = _mm_set1_ps(kInfinity);
    __m128i best_bin = _mm_setzero_si128();
    for (int b = 0; b < n_bins - 1; ++b) {
      ax.extend(bins[0][b].box);
      ay.extend(bins[1][b].box);
      az.extend(bins[2][b].box);
      n = _mm_add_epi32(n, counts(b));
      const __m128 cost = _mm_add_ps(_mm_mul_ps(half_areas(ax, ay, az), blocks4(n)), right_cost[b]);
      // 0 < n < count (counts are far below 2^31, so signed compares are exact)
      const __m128i usable =
          _mm_and_si128(_mm_and_si128(axes, xyz),
                        _mm_andnot_si128(_mm_cmpeq_epi32(n, _mm_setzero_si128()), _mm_cmplt_epi32(n, total)));
      const __m128 better = _mm_and_ps(_mm_castsi128_ps(usable), _mm_cmplt_ps(cost, best_cost));
      best_cost = _mm_or_ps(_mm_and_ps(better, cost), _mm_andnot_ps(better, best_cost));  // SSE2 select
      const __m128i take = _mm_castps_si128(better);
      best_bin = _mm_or_si128(_mm_and_si128(take, _mm_set1_epi32(b)), _mm_andnot_si128(take, best_bin));
    }
    alignas(16) float c[4];
    alignas(16) int32_t bin[4];
    _mm_store_ps(c, best_cost);
    _mm_store_si128(reinterpret_cast<__m128i*>(bin), best_bin);
    Split best;
    for (int a = 0; a < 3; ++a)
      if (c[a] < best.cost) best = {a, bin[a], c[a]};
    return best;
  }

  RangeBounds bounds_of(uint32_t begin, uint32_t end) const {
    RangeBounds b;
    for (uint32_t i = begin; i < end; ++i) b.extend(refs[i]);
    return b;
  }

  /// Splits a task in two, or returns false to make it a leaf.
  bool split(const Task& t, Task& left, Task& right, Bin (*bins)[kMaxBins]) const {
    const uint32_t count = t.end - t.begin;
    if (count == 1) return false;
    Split s;
    const Binning binning = make_binning(t);
    if (t.depth < kSahDepthLimit) s = find_split(t, binning, bins);
    uint32_t mid = t.begin;
    if (s.axis >= 0) {
      const float area = t.bounds.box.half_area();
      if (area * blocks(count) <= options.traversal_cost * area + s.cost && count <= max_leaf) return false;
      // Partition in place, collecting both sides' box and centroid bounds on the way.
      const int a = s.axis;
      RangeBounds lb, rb;
      uint32_t i = t.begin, j = t.end;
      // The side test compares all three bin indices with the split bin and reads the axis' bit of the mask: a
      // lane picked by a run-time axis went through the stack, the partition's hottest instructions in perf.
      const __m128i split_bin = _mm_set1_epi32(s.bin);
      const int axis_bit = 1 << a;
      auto right_side = [&](__m128 center2) {
        return _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(binning.index_of(center2), split_bin))) & axis_bit;
      };
      for (;;) {
        for (; i < j; ++i) {
          const __m128 c = refs[i].center2();
          if (right_side(c)) break;
          lb.extend(refs[i], c);
        }
        for (; i < j; --j) {
          const __m128 c = refs[j - 1].center2();
          if (!right_side(c)) break;
          rb.extend(refs[j - 1], c);
        }
        if (i == j) break;
        std::swap(refs[i], refs[j - 1]);
      }
      mid = i;
      left = {0, t.begin, mid, t.depth + 1, lb};
      right = {0, mid, t.end, t.depth + 1, rb};
    }
    if (mid == t.begin || mid == t.end) {
      // No useful SAH split (all centroids equal, or too deep): a median split keeps the tree balanced.
      if (count <= max_leaf) return false;
      alignas(16) float extent[4];
      _mm_store_ps(extent, _mm_sub_ps(t.bounds.centroids.hi, t.bounds.centroids.lo));
      const int a = max_dimension(vec3(extent[0], extent[1], extent[2]));
      mid = t.begin + count / 2;
      std::nth_element(refs.begin() + t.begin, refs.begin() + mid, refs.begin() + t.end,
                       [&](const PrimRef& x, const PrimRef& y) { return x.center_axis(a) < y.center_axis(a); });
      left = {0, t.begin, mid, t.depth + 1, bounds_of(t.begin, mid)};
      right = {0, mid, t.end, t.depth + 1, bounds_of(mid, t.end)};
    }
    return true;
  }

  /// The root's split with the work inside the node shared by the build threads: at the top of the tree there is
  /// one node and nothing else to run, and its binning and partition over every reference were the largest serial
  /// part of a 2-thread build. The references are cut into contiguous chunks, each binned on its own (the merge is
  /// exact: min, max and integer counts); the partition is stable and out of place (each chunk knows from its own
  /// bins how many of its references go left, so it knows where to write them), then copied back. A stable
  /// partition does not depend on the chunks, so the tree is the same for any thread count. Returns false where the
  /// serial split must decide (no SAH split: the median fallback, or a leaf).
  bool split_root(const Task& t, Task& left, Task& right) {
    const uint32_t count = t.end - t.begin;
    const Binning binning = make_binning(t);
    const int chunks_max = std::min(threads, 64);
    struct ChunkBins {
      Bin bins[3][kMaxBins];
    };
    std::vector<ChunkBins> chunk_bins(static_cast<size_t>(chunks_max));
    auto bins_of = [&](int c) { return chunk_bins[static_cast<size_t>(c)].bins; };
    const int chunks = parallel_chunk_count(count, chunks_max, kMinParallelPrims);
    parallel_chunks(count, chunks_max, kMinParallelPrims, [&](int c, size_t begin, size_t end) {
      bin_range(t.begin + uint32_t(begin), t.begin + uint32_t(end), binning, bins_of(c));
    });
    Bin merged[3][kMaxBins];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < binning.bins; ++b) {
        merged[a][b] = Bin{};
        for (int c = 0; c < chunks; ++c) {
          merged[a][b].box.extend(bins_of(c)[a][b].box);
          merged[a][b].count += bins_of(c)[a][b].count;
        }
      }
    const Split s = sweep(merged, binning.bins, count, _mm_sub_ps(t.bounds.centroids.hi, t.bounds.centroids.lo));
    if (s.axis < 0) return false;
    // Where each chunk's references go: left ones from left_at[c], right ones from right_at[c].
    std::vector<uint32_t> left_at(static_cast<size_t>(chunks)), right_at(static_cast<size_t>(chunks));
    uint32_t n_left = 0;
    for (int c = 0; c < chunks; ++c) {
      left_at[size_t(c)] = n_left;
      for (int b = 0; b <= s.bin; ++b) n_left += bins_of(c)[s.axis][b].count;
    }
    if (n_left == 0 || n_left == count) return false;
    for (int c = 0, n_right = 0; c < chunks; ++c) {
      right_at[size_t(c)] = n_left + uint32_t(n_right);
      for (int b = s.bin + 1; b < binning.bins; ++b) n_right += int(bins_of(c)[s.axis][b].count);
    }
    struct Free {
      size_t n;
      void operator()(PrimRef* p) const { HugePageAllocator<PrimRef>().deallocate(p, n); }
    };
    const std::unique_ptr<PrimRef[], Free> spare(HugePageAllocator<PrimRef>().allocate(count), Free{count});
    std::vector<RangeBounds> lb(static_cast<size_t>(chunks)), rb(static_cast<size_t>(chunks));
    const __m128i split_bin = _mm_set1_epi32(s.bin);
    const int axis_bit = 1 << s.axis;
    parallel_chunks(count, chunks_max, kMinParallelPrims, [&](int c, size_t begin, size_t end) {
      uint32_t l = left_at[size_t(c)], r = right_at[size_t(c)];
      for (size_t i = t.begin + begin; i < t.begin + end; ++i) {
        const __m128 center = refs[i].center2();
        const bool right_side =
            _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(binning.index_of(center), split_bin))) & axis_bit;
        (right_side ? rb : lb)[size_t(c)].extend(refs[i], center);
        spare[right_side ? r++ : l++] = refs[i];
      }
    });
    parallel_chunks(count, chunks_max, kMinParallelPrims, [&](int, size_t begin, size_t end) {
      std::copy(spare.get() + begin, spare.get() + end, refs.begin() + t.begin + begin);
    });
    RangeBounds lbox, rbox;
    for (int c = 0; c < chunks; ++c) lbox.extend(lb[size_t(c)]), rbox.extend(rb[size_t(c)]);
    left = {0, t.begin, t.begin + n_left, t.depth + 1, lbox};
    right = {0, t.begin + n_left, t.end, t.depth + 1, rbox};
    return true;
  }

  /// A subtree built as one unit of work into its own node vector (its root is nodes[0]). Every child task of
  /// kMinParallelPrims or more primitives becomes a job of its own, whatever the thread count, so the jobs and
  /// therefore the final node order (stitch) are the same for any number of threads: the build is deterministic.
  struct Job {
    Task task;
    /// Its nodes: arenas[arena][offset, offset + size), local index i at offset + i. A job runs on one thread from
    /// start to end, so its nodes are contiguous in that thread's arena.
    uint32_t arena = 0;
    size_t offset = 0, size = 0;
    std::vector<std::pair<uint32_t, std::unique_ptr<Job>>> children;  ///< (placeholder node of this job, job)
  };
  /// One node arena per thread, in huge pages and reused by all the thread's jobs: a vector per job meant a fresh
  /// allocation, and a page fault per 4 KiB of nodes, for every job.
  std::vector<HugeVector<BvhNode>> arenas;

  /// Jobs waiting for a thread; `unfinished` counts queued and running jobs.
  std::mutex queue_mutex;
  std::condition_variable queue_cv;
  std::vector<Job*> queue;
  size_t unfinished = 0;

  void enqueue(Job* job) {
    {
      std::lock_guard<std::mutex> lock(queue_mutex);
      queue.push_back(job);
      ++unfinished;
    }
    queue_cv.notify_one();
  }

  /// Takes jobs until all are done (the main thread and the helper threads alike).
  void work(uint32_t arena) {
    Bin bins[3][kMaxBins];  // scratch, reused by every node this thread splits
    int local_depth = 0;
    for (;;) {
      Job* job;
      {
        std::unique_lock<std::mutex> lock(queue_mutex);
        queue_cv.wait(lock, [&] { return !queue.empty() || unfinished == 0; });
        if (queue.empty()) break;
        job = queue.back();
        queue.pop_back();
      }
      run(*job, arena, bins, local_depth);
      bool all_done;
      {
        std::lock_guard<std::mutex> lock(queue_mutex);
        all_done = --unfinished == 0;
      }
      if (all_done) queue_cv.notify_all();
    }
    int d = depth.load();
    while (local_depth > d && !depth.compare_exchange_weak(d, local_depth)) {}
  }

  /// Builds the subtree of job.task into job.nodes; children of kMinParallelPrims or more become new jobs.
  void run(Job& job, uint32_t arena, Bin (*bins)[kMaxBins], int& local_depth) {
    HugeVector<BvhNode>& all = arenas[arena];
    job.arena = arena;
    job.offset = all.size();
    BvhNode* nodes = nullptr;  // job-local indexing; set again whenever the arena may have grown
    auto grow = [&](size_t count) {
      all.resize(all.size() + count);
      nodes = all.data() + job.offset;
    };
    grow(1);
    std::vector<Task> stack{job.task};
    stack.back().node = 0;
    while (!stack.empty()) {
      Task t = stack.back();
      stack.pop_back();
      local_depth = std::max(local_depth, t.depth);
      nodes[t.node].bounds = t.bounds.box.aabb();
      Task children[2];
      const bool root_chunked = t.depth == 0 && t.end - t.begin >= kMinChunkedRootPrims;
      if (!(root_chunked && split_root(t, children[0], children[1])) && !split(t, children[0], children[1], bins)) {
        nodes[t.node].first = t.begin;
        nodes[t.node].count = t.end - t.begin;
        continue;
      }
      const uint32_t first = uint32_t(all.size() - job.offset);
      nodes[t.node].first = first;
      nodes[t.node].count = 0;
      grow(2);
      for (int k = 1; k >= 0; --k) {  // right pushed first: the left subtree is built first
        Task& c = children[k];
        c.node = first + uint32_t(k);
        if (c.end - c.begin >= kMinParallelPrims) {
          auto child = std::make_unique<Job>();
          child->task = c;
          Job* raw = child.get();
          job.children.emplace_back(c.node, std::move(child));
          enqueue(raw);
        } else {
          stack.push_back(c);
        }
      }
    }
    job.size = all.size() - job.offset;
  }

  /// Appends `job`'s nodes to `out`, its root going to out[slot] (the root job: out is empty), then its child jobs
  /// in the order they were made, with every child index shifted to its place in `out`.
  void stitch(Job& job, uint32_t slot, HugeVector<BvhNode>& out) const {
    const BvhNode* nodes = arenas[job.arena].data() + job.offset;
    const bool root = out.empty();
    const uint32_t base = root ? 0u : uint32_t(out.size()) - 1u;  // node i >= 1 goes to base + i
    auto moved = [&](BvhNode n) {
      if (!n.is_leaf()) n.first += base;
      return n;
    };
    if (root) out.push_back(moved(nodes[0]));
    else out[slot] = moved(nodes[0]);
    for (size_t i = 1; i < job.size; ++i) out.push_back(moved(nodes[i]));
    for (auto& [local_slot, child] : job.children) stitch(*child, local_slot + base, out);
  }

  /// Builds the whole tree with `threads` threads (the caller's included) into `out`.
  void build(const Task& root, int thread_count, HugeVector<BvhNode>& out) {
    threads = thread_count;
    Job root_job;
    root_job.task = root;
    // A tree over n primitives has at most 2n - 1 nodes, so no arena reallocates (untouched capacity costs nothing).
    arenas.resize(size_t(threads));
    for (HugeVector<BvhNode>& a : arenas) a.reserve(2 * size_t(root.end - root.begin));
    enqueue(&root_job);
    std::vector<std::thread> helpers;
    for (int i = 1; i < threads; ++i) helpers.emplace_back([this, i] { work(uint32_t(i)); });
    work(0);
    for (std::thread& h : helpers) h.join();
    stitch(root_job, 0, out);
  }
};

/// Makes the references (box_of(i) is primitive i's box) in parallel chunks and builds the tree over them.
template <class BoxOf>
Bvh build_from(uint32_t n, const BvhBuildOptions& options, BoxOf&& box_of) {
  Bvh bvh;
  if (n == 0) return bvh;
  const int threads = build_threads(options.threads);
  // Raw storage, not a vector: value-initializing the references was a serial memset of 32n bytes.
  struct Free {
    size_t n;
    void operator()(PrimRef* p) const { HugePageAllocator<PrimRef>().deallocate(p, n); }
  };
  const std::unique_ptr<PrimRef[], Free> storage(HugePageAllocator<PrimRef>().allocate(n), Free{n});
  const std::span<PrimRef> refs(storage.get(), n);
  RangeBounds part[64];
  const int parts = std::min(threads, 64);
  parallel_chunks(n, parts, kMinParallelPrims, [&](int chunk, size_t begin, size_t end) {
    RangeBounds b;
    for (uint32_t i = uint32_t(begin); i < end; ++i) {
      refs[i].set(box_of(i), i);
      b.extend(refs[i]);
    }
    part[chunk] = b;  // min and max: the same bounds however the chunks fall
  });
  RangeBounds all;
  for (const RangeBounds& b : part) all.extend(b);
  bvh.nodes.reserve(2 * size_t(n));
  Builder b(refs, options);
  b.build({0, 0, n, 0, all}, threads, bvh.nodes);
  bvh.depth = b.depth.load();
  bvh.prim_indices.resize(n);
  parallel_chunks(n, threads, kMinParallelPrims, [&](int, size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) bvh.prim_indices[i] = refs[i].id();
  });
  return bvh;
}

}  // namespace

Bvh build_bvh(std::span<const AABB> boxes, const BvhBuildOptions& options) {
  return build_from(uint32_t(boxes.size()), options, [&](uint32_t i) { return boxes[i]; });
}

Bvh build_triangle_bvh(std::span<const vec3> vertices, const BvhBuildOptions& options) {
  return build_from(uint32_t(vertices.size() / 3), options, [&](uint32_t i) {
    AABB b;
    for (int k = 0; k < 3; ++k) b.extend(vertices[3 * size_t(i) + k]);
    return b;
  });
}

float sah_cost(const Bvh& bvh, float traversal_cost) {
  if (bvh.nodes.empty()) return 0.0f;
  double root = bvh.nodes[0].bounds.half_area();
  if (!(root > 0.0)) return 0.0f;
  double cost = 0.0;
  for (const BvhNode& node : bvh.nodes) {
    double a = node.bounds.half_area() / root;
    cost += node.is_leaf() ? a * node.count : a * traversal_cost;
  }
  return float(cost);
}

}  // namespace pt
