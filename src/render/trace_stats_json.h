#pragma once
/// The "bvh" object of the stats JSON, shared by the headless runner and the viewer.
#include <nlohmann/json.hpp>

#include "accel/geometry.h"

namespace pt {

inline nlohmann::json trace_stats_json(const TraceGeometry& g) {
  const TraceStats& s = g.stats;
  return {{"build_ms", s.build_ms},
          {"nodes", s.wide_nodes + g.sphere_bvh.nodes.size()},
          {"binary_nodes", s.binary_nodes},
          {"leaf_blocks", s.leaf_blocks},
          {"depth", s.depth},
          {"sah_cost", s.sah_cost},
          {"bytes", s.memory_bytes},
          {"simd", bvh8_simd_name()},
          {"primitives", g.primitive_count()}};
}

}  // namespace pt
