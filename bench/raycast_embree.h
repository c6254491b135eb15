#pragma once
/// The Embree 3 side of bench/raycast: a triangle scene built from the same vertex triples as ours, traced one ray
/// at a time. Compiled against Embree only when CMake found it (PTVIEW_HAVE_EMBREE); otherwise every function is
/// a stub and embree_available() is false, so bench/raycast.cpp needs no #ifdef.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "core/ray.h"

namespace bench {

/// Peak memory of a piece of code, measured the same way for both builders: return freed heap memory to the
/// system (malloc_trim), reset the kernel's peak-RSS mark (write "5" to /proc/self/clear_refs), run the code, then
/// read VmHWM - VmRSS(before) from /proc/self/status. It counts every page the code touched and still had resident
/// at its peak (results, temporaries, thread stacks), whoever allocated it. Returns -1 when /proc does not allow it.
class PeakRssProbe {
 public:
  PeakRssProbe();           ///< trims, resets the mark, records VmRSS
  double growth() const;    ///< bytes: VmHWM now minus VmRSS at construction, or -1
 private:
  double rss_before_ = -1.0;
};

bool embree_available();
std::string embree_version();  ///< "3.13.5", or "" without Embree

enum class EmbreeQuality { medium, high };

/// What one rtcCommitScene cost.
struct EmbreeBuildFigures {
  double ms = 0.0;              ///< wall time of rtcCommitScene
  double net_bytes = 0.0;       ///< bytes Embree holds after the commit minus before (memory monitor)
  double monitor_peak = 0.0;    ///< highest bytes held during the commit minus before (memory monitor)
  double rss_peak = 0.0;        ///< growth of the process's peak RSS during the commit (see PeakRssProbe)
};

/// An Embree device plus a committed scene with one triangle geometry; primID = triangle index of the input.
class EmbreeScene {
 public:
  /// `device_threads` 0: Embree's default (all hardware threads); otherwise the device config "threads=N" (it only
  /// affects the build: tracing runs on the calling threads).
  EmbreeScene(std::span<const pt::vec3> triangle_vertices, EmbreeQuality quality, int device_threads);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  const EmbreeBuildFigures& build() const { return build_; }

  /// Closest hit in [0, ray.tmax] (tnear 0, mask -1, flags 0). Returns false on a miss.
  bool intersect(const pt::Ray& ray, float& t, uint32_t& prim) const;
  /// True if anything is hit in [0, ray.tmax].
  bool occluded(const pt::Ray& ray) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  EmbreeBuildFigures build_;
};

}  // namespace bench
