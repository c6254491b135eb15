#pragma once
/// The "bvh" object of the stats JSON, shared by the headless runner and the viewer.
#include <nlohmann/json.hpp>

#include "accel/geometry.h"

namespace pt {

inline nlohmann::json trace_stats_json(const TraceGeometry& g) {
  const TraceStats& s = g.stats;
  return {{"build_ms", s.build_ms},
          {"nodes", g.triangles.node_count + g.sphere_bvh.nodes.size()},
          {"binary_nodes", s.binary_nodes},
          {"leaf_blocks", g.triangles.block_count},
          {"depth", s.depth},
          {"sah_cost", s.sah_cost},
          {"bytes", s.memory_bytes},
          {"simd", bvh8_simd_name()},
          {"primitives", g.primitive_count()}};
}

}  // namespace pt
