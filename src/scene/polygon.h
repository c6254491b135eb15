#pragma once
/// Triangulation of the polygons of OBJ faces. tinyobjloader's own (rc10) splits quads well but its ear clipper
/// for larger polygons can flip or drop triangles; and doing it here keeps each triangle tied to its face's line.
#include <span>
#include <vector>

#include "core/math.h"

namespace pt {

/// Triangulates a simple planar (or nearly planar) polygon given by its corners in order, appending triangles as
/// index triples into `corners` that keep the polygon's winding (so its front side). A quad is split along its
/// shorter diagonal unless only the other one lies inside it (a concave quad); larger polygons by ear clipping in
/// the plane of their Newell normal (Eberly, "Triangulation by Ear Clipping", 2002; Newell's normal: Sutherland et
/// al. 1974), which handles concave polygons. A polygon with no area, or one the clipper cannot finish
/// (self-intersecting), falls back to a fan: its degenerate triangles are then dropped by the caller. Always
/// appends corners.size() - 2 triangles.
void triangulate_polygon(std::span<const vec3> corners, std::vector<uvec3>& out);

}  // namespace pt
