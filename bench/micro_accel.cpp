// Micro benchmarks of the innermost kernels (Google Benchmark): the watertight ray-triangle test, the ray-box slab
// test and the sampling warps. Every benchmark runs over the same fixed batch of kCount precomputed random inputs
// (rays, triangles, boxes, uniform numbers: nothing random is drawn inside the timed loop) and reports items/s =
// tests or samples per second. Hits and misses are mixed; `hit_rate` tells the fraction.
//   build/bench/bench_micro_accel [--benchmark_filter=triangle] [--benchmark_min_time=1]
// The wide BVH's kernels: the 8-box node test (SIMD and its scalar reference) over groups of 8 boxes of the batch,
// and the 4-lane triangle test over groups of 4 triangles; items are boxes or triangles tested, so their rates
// compare directly with the one-at-a-time tests.
#include <benchmark/benchmark.h>

#include <array>
#include <bit>
#include <random>
#include <vector>

#include "accel/bvh.h"
#include "accel/bvh8.h"
#include "accel/sphere.h"
#include "accel/triangle.h"
#include "core/sampling.h"
#include "render/sampler.h"

using namespace pt;

namespace {

constexpr size_t kCount = 4096;  // items per batch: a power of two, small enough to stay in L1/L2

/// The fixed inputs, built once: ray i is aimed near triangle i (about half of the pairs hit) and box i bounds
/// triangle i.
struct Batch {
  std::vector<Ray> rays;
  std::vector<WatertightRay> tri_rays;
  std::vector<RayBoxData> box_rays;
  std::vector<std::array<vec3, 3>> triangles;
  std::vector<AABB> boxes;
  std::vector<vec2> u;      // uniform numbers in [0,1)^2 for the warps
  std::vector<vec3> refs;   // shading points below the rectangle light, for the spherical-rectangle warp
  std::vector<NodeRay> node_rays;
  std::vector<Bvh8Node> nodes;  // node k holds boxes 8k .. 8k+7
  std::vector<Tri4> blocks;     // block k holds triangles 4k .. 4k+3
};

const Batch& batch() {
  static const Batch b = [] {
    Batch d;
    std::mt19937 gen(12345);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    auto in_cube = [&](float half) { return half * vec3(2 * U(gen) - 1, 2 * U(gen) - 1, 2 * U(gen) - 1); };
    for (size_t i = 0; i < kCount; ++i) {
      vec3 c = in_cube(1.0f);
      std::array<vec3, 3> t{c + in_cube(0.3f), c + in_cube(0.3f), c + in_cube(0.3f)};
      vec3 centroid = (t[0] + t[1] + t[2]) / 3.0f;
      vec3 org = in_cube(4.0f);
      vec3 aim = centroid + in_cube(0.08f);  // near the centroid: roughly half hit
      Ray r{org, glm::normalize(aim - org), kInfinity};
      AABB box;
      for (vec3 p : t) box.extend(p);
      d.rays.push_back(r);
      d.tri_rays.push_back(make_watertight_ray(r));
      d.box_rays.push_back(make_ray_box_data(r));
      d.triangles.push_back(t);
      d.boxes.push_back(box);
      d.u.push_back(vec2(U(gen), U(gen)));
      d.refs.push_back(vec3(4 * U(gen) - 2, -0.5f - 2 * U(gen), 4 * U(gen) - 2));
    }
    for (size_t k = 0; k < kCount / 8; ++k) {
      Bvh8Node n;
      for (int s = 0; s < 8; ++s) {
        set_slot(n, s, d.boxes[8 * k + s]);
        n.child[s] = uint32_t(s);
      }
      d.nodes.push_back(n);
    }
    for (size_t k = 0; k < kCount / 4; ++k) {
      Tri4 blk;
      for (int lane = 0; lane < 4; ++lane) {
        const auto& t = d.triangles[4 * k + lane];
        blk.prim[lane] = uint32_t(4 * k + lane);
        set_lane(blk, lane, t[0], t[1], t[2]);
      }
      d.blocks.push_back(blk);
    }
    for (const Ray& r : d.rays) d.node_rays.push_back(make_node_ray(r));
    return d;
  }();
  return b;
}

/// Runs f(i) for every item of the batch per benchmark iteration; f returns whether item i counts as a hit.
template <class F>
void run_batch(benchmark::State& state, F&& f) {
  size_t hits = 0;
  for (auto _ : state)
    for (size_t i = 0; i < kCount; ++i) hits += f(i) ? 1 : 0;
  double items = double(state.iterations()) * double(kCount);
  state.SetItemsProcessed(int64_t(items));
  if (hits > 0) state.counters["hit_rate"] = double(hits) / items;  // warps return false: no counter
}

void BM_intersect_triangle(benchmark::State& state) {
  const Batch& d = batch();
  run_batch(state, [&](size_t i) {
    const auto& t = d.triangles[i];
    TriangleHit hit;
    bool h = intersect_triangle(d.tri_rays[i], kInfinity, t[0], t[1], t[2], hit);
    benchmark::DoNotOptimize(hit);
    return h;
  });
}
BENCHMARK(BM_intersect_triangle);

// The per-ray setup is done once per ray in traversal; measured alone here.
void BM_make_watertight_ray(benchmark::State& state) {
  const Batch& d = batch();
  run_batch(state, [&](size_t i) {
    WatertightRay w = make_watertight_ray(d.rays[i]);
    benchmark::DoNotOptimize(w);
    return false;
  });
}
BENCHMARK(BM_make_watertight_ray);

void BM_intersect_box(benchmark::State& state) {
  const Batch& d = batch();
  // Even items test the ray's own box (nearly always a hit), odd items a neighbour's box (mostly a miss).
  run_batch(state, [&](size_t i) {
    float t = intersect_box(d.boxes[i ^ (i & 1)], d.box_rays[i], kInfinity);
    benchmark::DoNotOptimize(t);
    return t != kInfinity;
  });
}
BENCHMARK(BM_intersect_box);

/// Runs f(k) for every group of `group` items per iteration; f returns how many of the group hit.
template <class F>
void run_groups(benchmark::State& state, size_t group, F&& f) {
  size_t hits = 0;
  for (auto _ : state)
    for (size_t k = 0; k < kCount / group; ++k) hits += f(k);
  const double items = double(state.iterations()) * double(kCount);
  state.SetItemsProcessed(int64_t(items));
  state.counters["hit_rate"] = double(hits) / items;
}

// Group k is tested with ray 8k (ray 8k aims near box 8k, so about one box in 8 or more is hit).
template <bool kSimd>
void BM_node8(benchmark::State& state) {
  const Batch& d = batch();
  run_groups(state, 8, [&](size_t k) {
    alignas(32) float tnear[8];
    const uint32_t mask = kSimd ? intersect_node8(d.nodes[k], d.node_rays[8 * k], kInfinity, tnear)
                                : intersect_node8_scalar(d.nodes[k], d.node_rays[8 * k], kInfinity, tnear);
    benchmark::DoNotOptimize(tnear);
    return size_t(std::popcount(mask));
  });
}
BENCHMARK(BM_node8<true>)->Name("BM_node8_simd");
BENCHMARK(BM_node8<false>)->Name("BM_node8_scalar");

// Block k is tested with ray 4k (aimed near triangle 4k); closest hit of the four.
void BM_tri4(benchmark::State& state) {
  const Batch& d = batch();
  run_groups(state, 4, [&](size_t k) {
    const Tri4Hit h = intersect_tri4(d.blocks[k], d.tri_rays[4 * k], kInfinity);
    benchmark::DoNotOptimize(h);
    return size_t(h.lane >= 0);
  });
}
BENCHMARK(BM_tri4);

template <class Warp>
void warp_benchmark(benchmark::State& state, Warp warp) {
  const Batch& d = batch();
  run_batch(state, [&](size_t i) {
    auto v = warp(d.u[i]);
    benchmark::DoNotOptimize(v);
    return false;
  });
}
void BM_sample_cosine_hemisphere(benchmark::State& s) { warp_benchmark(s, sample_cosine_hemisphere); }
void BM_sample_uniform_disk_concentric(benchmark::State& s) { warp_benchmark(s, sample_uniform_disk_concentric); }
void BM_sample_uniform_sphere(benchmark::State& s) { warp_benchmark(s, sample_uniform_sphere); }
void BM_sample_uniform_triangle(benchmark::State& s) { warp_benchmark(s, sample_uniform_triangle); }
BENCHMARK(BM_sample_cosine_hemisphere);
BENCHMARK(BM_sample_uniform_disk_concentric);
BENCHMARK(BM_sample_uniform_sphere);
BENCHMARK(BM_sample_uniform_triangle);

/// The rectangle light of the spherical-rectangle benchmarks: 1 x 1 in the plane y = 1, the shading points below
/// it. Its frame is made once, as render/light.cpp keeps it per light.
RectangleFrame bench_rectangle() {
  RectangleFrame rect;
  make_rectangle_frame(vec3(-0.5f, 1.0f, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1), rect);
  return rect;
}

// Spherical rectangle (Urena et al. 2013): the per-shading-point setup plus one sample, as light sampling does it.
void BM_spherical_rectangle(benchmark::State& state) {
  const Batch& d = batch();
  const RectangleFrame rect = bench_rectangle();
  run_batch(state, [&](size_t i) {
    SphericalRectangle sr;
    bool ok = make_spherical_rectangle(d.refs[i], rect, sr);
    vec3 p = ok ? sample_spherical_rectangle(sr, d.u[i]) : vec3(0.0f);
    benchmark::DoNotOptimize(p);
    return ok;
  });
}
BENCHMARK(BM_spherical_rectangle);

// The two halves of the above on their own: the setup alone, then the sample from setups made beforehand (where
// the time of a rectangle sample goes; setup and sample together cost more than the sum, the sample waiting on
// the setup).
void BM_spherical_rectangle_setup(benchmark::State& state) {
  const Batch& d = batch();
  const RectangleFrame rect = bench_rectangle();
  run_batch(state, [&](size_t i) {
    SphericalRectangle sr;
    const bool ok = make_spherical_rectangle(d.refs[i], rect, sr);
    benchmark::DoNotOptimize(sr);
    return ok;
  });
}
BENCHMARK(BM_spherical_rectangle_setup);

void BM_spherical_rectangle_sample(benchmark::State& state) {
  const Batch& d = batch();
  const RectangleFrame rect = bench_rectangle();
  std::vector<SphericalRectangle> setups(kCount);
  for (size_t i = 0; i < kCount; ++i) make_spherical_rectangle(d.refs[i], rect, setups[i]);
  run_batch(state, [&](size_t i) {
    const vec3 p = sample_spherical_rectangle(setups[i], d.u[i]);
    benchmark::DoNotOptimize(p);
    return true;
  });
}
BENCHMARK(BM_spherical_rectangle_sample);

// Ray against sphere (accel/sphere.h, double precision): ray i against a sphere of radius 0.1 at triangle i's
// centroid, which it is aimed near (even items, mostly hits), or at its even neighbour's (odd items, mostly misses).
void BM_intersect_sphere(benchmark::State& state) {
  const Batch& d = batch();
  run_batch(state, [&](size_t i) {
    const auto& t = d.triangles[i ^ (i & 1)];
    const float hit_t = intersect_sphere(d.rays[i], (t[0] + t[1] + t[2]) / 3.0f, 0.1f, kInfinity);
    benchmark::DoNotOptimize(hit_t);
    return hit_t < kInfinity;
  });
}
BENCHMARK(BM_intersect_sphere);

/// Setup at each shading point of the batch plus one sample, for a spherical shape S made by `make` and sampled by
/// `sample` from a light in the plane y = 1 with corner (-0.5, 1, -0.5) and edges e1, e2.
template <class S, bool (*make)(vec3, vec3, vec3, vec3, S&), vec3 (*sample)(const S&, vec2)>
void spherical_setup_and_sample(benchmark::State& state, vec3 e1, vec3 e2) {
  const Batch& d = batch();
  run_batch(state, [&](size_t i) {
    S shape;
    bool ok = make(d.refs[i], vec3(-0.5f, 1.0f, -0.5f), e1, e2, shape);
    vec3 p = ok ? sample(shape, d.u[i]) : vec3(0.0f);
    benchmark::DoNotOptimize(p);
    return ok;
  });
}

// Spherical triangle (Arvo 1995): the same, for half of that rectangle, as triangle lights do it.
void BM_spherical_triangle(benchmark::State& state) {
  spherical_setup_and_sample<SphericalTriangle, make_spherical_triangle, sample_spherical_triangle>(
      state, vec3(1, 0, 0), vec3(0, 0, 1));
}
BENCHMARK(BM_spherical_triangle);

// Spherical parallelogram (two spherical triangles): a 1 x 1 quad sheared by 45 degrees, as sheared quad lights do it.
void BM_spherical_parallelogram(benchmark::State& state) {
  spherical_setup_and_sample<SphericalParallelogram, make_spherical_parallelogram, sample_spherical_parallelogram>(
      state, vec3(1, 0, 0), vec3(0.5f, 0, 1));
}
BENCHMARK(BM_spherical_parallelogram);

// The random numbers of one pixel sample as the path tracer draws them for a path of 3 vertices: the seeding, the
// camera's 2D draw and per vertex a 4D and a 3D draw (render/integrator.cpp); items = pixel samples (issue 11).
template <SamplerKind kind>
void BM_pixel_sampler(benchmark::State& state) {
  uint64_t n = 0;
  for (auto _ : state) {
    PixelSampler s = PixelSampler::start(7, n >> 6, n & 63u, kind);
    ++n;
    vec2 c = s.next2d();
    float acc = c.x + c.y;
    for (int v = 0; v < 3; ++v) {
      float a[4], b[3];
      s.next<4>(a);
      s.next<3>(b);
      acc += a[0] + a[1] + a[2] + a[3] + b[0] + b[1] + b[2];
    }
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_pixel_sampler<SamplerKind::independent>)->Name("BM_pixel_sampler_independent");
BENCHMARK(BM_pixel_sampler<SamplerKind::sobol>)->Name("BM_pixel_sampler_sobol");

// The latency of a pixel sample's first draw (the camera's): each sample's pixel depends on the previous draw, so
// the loop runs the seeding and the draw as one dependent chain, as the path tracer does after the previous path's
// last branch (fourteenth round).
template <SamplerKind kind>
void BM_camera_draw_latency(benchmark::State& state) {
  const SamplerKeys keys(7);
  uint64_t n = 0;
  float acc = 0.0f;
  for (auto _ : state) {
    PixelSampler s = PixelSampler::start(keys, (n >> 6) + (acc > 2.0f ? 1u : 0u), n & 63u, kind);
    ++n;
    const vec2 c = s.next2d();
    acc = c.x + c.y;
  }
  benchmark::DoNotOptimize(acc);
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_camera_draw_latency<SamplerKind::independent>)->Name("BM_camera_draw_latency_independent");
BENCHMARK(BM_camera_draw_latency<SamplerKind::sobol>)->Name("BM_camera_draw_latency_sobol");

}  // namespace
