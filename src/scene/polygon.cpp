#include "scene/polygon.h"

namespace pt {

namespace {

using dvec2 = glm::dvec2;

double cross2(dvec2 a, dvec2 b) { return a.x * b.y - a.y * b.x; }

/// p inside or on the triangle (a, b, c), which is counter-clockwise.
bool in_triangle(dvec2 p, dvec2 a, dvec2 b, dvec2 c) {
  return cross2(b - a, p - a) >= 0.0 && cross2(c - b, p - b) >= 0.0 && cross2(a - c, p - c) >= 0.0;
}

void fan(size_t n, std::vector<uvec3>& out) {
  for (uint32_t k = 1; k + 1 < n; ++k) out.push_back({0u, k, k + 1});
}

}  // namespace

void triangulate_polygon(std::span<const vec3> corners, std::vector<uvec3>& out) {
  const size_t n = corners.size();
  if (n < 3) return;
  if (n == 3) {
    out.push_back({0u, 1u, 2u});
    return;
  }
  if (n == 4) {
    // The shorter diagonal gives the better-shaped pair, but only a diagonal inside the quad is right. In a concave
    // quad (a dart) that is the one through the reflex corner, which can be the longer: the other one's two
    // triangles overlap, one of them facing backwards. A diagonal is inside when its two triangles face the same
    // way (in double, so the products of float differences cannot overflow; rounding can flip the sign only for a
    // nearly flat triangle, where either diagonal covers the quad about equally well).
    const dvec3 c0(corners[0]), c1(corners[1]), c2(corners[2]), c3(corners[3]);
    const bool inside02 = glm::dot(glm::cross(c1 - c0, c2 - c0), glm::cross(c2 - c0, c3 - c0)) > 0.0;
    const bool inside13 = glm::dot(glm::cross(c2 - c1, c3 - c1), glm::cross(c3 - c1, c0 - c1)) > 0.0;
    const bool use02 = inside02 != inside13 ? inside02 : glm::length(c2 - c0) <= glm::length(c3 - c1);
    if (use02) {
      out.push_back({0u, 1u, 2u});
      out.push_back({0u, 2u, 3u});
    } else {
      out.push_back({0u, 1u, 3u});
      out.push_back({1u, 2u, 3u});
    }
    return;
  }
  // Newell's normal: robust for non-planar and concave polygons; it points to the side the winding faces.
  dvec3 normal(0.0);
  for (size_t i = 0; i < n; ++i) {
    dvec3 a(corners[i]), b(corners[(i + 1) % n]);
    normal += dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  double len = glm::length(normal);
  if (!(len > 0.0) || !std::isfinite(len)) return fan(n, out);
  normal /= len;
  // A basis (u, v) of the plane with u x v = normal: the polygon is counter-clockwise in (u, v) coordinates.
  dvec3 u = glm::normalize(std::abs(normal.x) > 0.9 ? glm::cross(normal, dvec3(0, 1, 0))
                                                    : glm::cross(normal, dvec3(1, 0, 0)));
  dvec3 v = glm::cross(normal, u);
  std::vector<dvec2> p(n);
  for (size_t i = 0; i < n; ++i) p[i] = {glm::dot(dvec3(corners[i]), u), glm::dot(dvec3(corners[i]), v)};

  std::vector<uint32_t> left(n);  // the corners not yet clipped, in order
  for (size_t i = 0; i < n; ++i) left[i] = uint32_t(i);
  size_t first = out.size();
  while (left.size() > 3) {
    size_t m = left.size();
    bool clipped = false;
    for (size_t k = 0; k < m && !clipped; ++k) {
      uint32_t a = left[(k + m - 1) % m], b = left[k], c = left[(k + 1) % m];
      if (cross2(p[b] - p[a], p[c] - p[b]) <= 0.0) continue;  // reflex or flat: not an ear
      bool empty = true;
      for (size_t j = 0; j < m && empty; ++j) {
        uint32_t q = left[j];
        if (q != a && q != b && q != c && p[q] != p[a] && p[q] != p[b] && p[q] != p[c])
          empty = !in_triangle(p[q], p[a], p[b], p[c]);
      }
      if (!empty) continue;
      out.push_back({a, b, c});
      left.erase(left.begin() + std::ptrdiff_t(k));
      clipped = true;
    }
    if (!clipped) {  // self-intersecting or numerically stuck: give up on clipping
      out.resize(first);
      return fan(n, out);
    }
  }
  out.push_back({left[0], left[1], left[2]});
}

}  // namespace pt
