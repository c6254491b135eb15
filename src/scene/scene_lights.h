#pragma once
/// The lights of a scene as a user sees and edits them: rectangle (parallelogram) quads, connected groups of
/// emissive triangles of one material (an OBJ's two-triangle ceiling light is one light), and emissive spheres.
/// Edits act on the Scene's shapes only; the render layer refits its BVH from the edited scene
/// (refit_render_geometry), so no light edit ever costs a rebuild. Triangle counts never change.
#include <string>
#include <vector>

#include "scene/scene.h"

namespace pt {

enum class SceneLightKind : uint8_t { quad, triangles, sphere };

struct SceneLight {
  SceneLightKind kind = SceneLightKind::quad;
  uint32_t shape = 0;               ///< index into Scene::quads or Scene::spheres, or the mesh (kind triangles)
  std::vector<uint32_t> triangles;  ///< kind triangles: the group's triangles in that mesh
  uint32_t material = 0;
};

/// Every emissive shape, grouped: quads and spheres one each; a mesh's emissive triangles joined by shared
/// vertices (same index or same position) and the same material form one light. Order: meshes, quads, spheres
/// (the order of the scene's triangles), so "light N" is stable while the scene's materials do not change.
std::vector<SceneLight> find_scene_lights(const Scene& scene);
/// The same after an edit of materials only, keeping the lights of `before` whose material no longer emits (an
/// intensity or colour edited to 0), in the same order: a light switched off stays in the viewer's list, to be
/// switched on again, instead of vanishing from it with the selection that pointed at it.
std::vector<SceneLight> find_scene_lights(const Scene& scene, const std::vector<SceneLight>& before);

/// Where a light is and how big: its center (area-weighted centroid for triangles), two in-plane unit axes u, v
/// (a quad's edges; for triangles two non-parallel boundary edges, so a parallelogram's sides) and its extent
/// along them (W x H; a sphere's diameter twice).
struct LightPlacement {
  vec3 center{0.0f};
  vec3 u{1, 0, 0}, v{0, 1, 0};
  vec2 size{0.0f};
};
LightPlacement light_placement(const Scene& scene, const SceneLight& light);

/// "NAME (rectangle 0.47 x 0.38)"-style label for lists.
std::string light_label(const Scene& scene, const SceneLight& light);

/// Moves the light so its center is `center`.
void move_light(Scene& scene, SceneLight& light, vec3 center);
/// Sets its extent along u and v to `size` about its center (affine in the u, v frame). False for spheres
/// (use scale_light) and for non-positive sizes.
bool resize_light(Scene& scene, SceneLight& light, vec2 size);
/// Scales it about its center by `factor` > 0 (a sphere's radius).
bool scale_light(Scene& scene, SceneLight& light, float factor);

/// Index into `lights` of the light that contains the scene primitive `prim` in the flattened order (mesh
/// triangles, then two triangles per quad, then spheres), or -1.
int light_of_primitive(const Scene& scene, const std::vector<SceneLight>& lights, uint32_t prim);

}  // namespace pt
