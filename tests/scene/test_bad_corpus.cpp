// Every malformed file in tests/data/bad gives one error line that starts with the file's path and, where the
// problem sits on a line, that line: "FILE:LINE: reason". The table below is the expected outcome of each file,
// written by reading the file, and every .json/.obj in the folder must be in it.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "scene/load.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

struct BadCase {
  const char* file;
  int line;            ///< 0: no line applies ("FILE: reason")
  const char* reason;  ///< a piece of the message
};

// clang-format off
const BadCase kCases[] = {
  // JSON syntax
  {"syntax_error.json",           3, "invalid JSON"},
  {"trailing_garbage.json",       3, "invalid JSON"},
  {"unterminated_string.json",    3, "invalid JSON"},
  {"nan_literal.json",            3, "invalid JSON"},
  {"empty.json",                  1, "invalid JSON"},
  {"binary_garbage.json",         1, "binary data"},
  {"huge_number.json",            3, "number overflow"},
  // JSON structure and types
  {"not_object.json",             1, "expected a JSON object at the top level"},
  {"missing_shapes.json",         1, "missing \"shapes\""},
  {"shapes_not_array.json",       2, "shapes: expected an array of shapes"},
  {"shape_not_object.json",       4, "shapes[1]: expected an object"},
  {"shape_without_type.json",     4, "shapes[0]: missing \"type\""},
  {"unknown_shape_type.json",     3, "unknown shape type 'cube'"},
  {"vector_wrong_length.json",    3, "shapes[0].corner: expected an array of 3 numbers"},
  {"vector_of_strings.json",      2, "background: expected an array of 3 numbers"},
  {"float_overflow.json",         4, "shapes[0].radius: expected a finite number"},
  {"bad_version.json",            2, "unsupported scene version 2"},
  {"version_string.json",         2, "unsupported scene version \"1\""},
  {"camera_not_object.json",      2, "camera: expected an object"},
  {"materials_not_object.json",   2, "materials: expected an object"},
  {"sphere_missing_radius.json",  3, "missing \"radius\""},
  {"quad_missing_edge.json",      3, "shapes[0]: missing \"edge2\""},
  {"mesh_without_file.json",      3, "missing \"file\""},
  {"material_ref_not_string.json", 5, "shapes[0].material: expected a string"},
  // JSON values
  {"unknown_material_type.json",  3, "unknown material type 'metal'"},
  {"unknown_material_ref.json",   5, "unknown material 'b'"},
  {"zero_area_quad_unknown_material.json", 4, "shapes[0].material: unknown material 'nowhere'"},
  {"camera_on_obj_mesh.json",     4, "shapes[0].camera: \"camera\" picks a camera of a .gltf/.glb file"},
  {"negative_radius.json",        4, "radius must be positive"},
  {"zero_radius.json",            1, "radius must be positive"},
  {"bad_ior.json",                3, "ior must be positive"},
  {"negative_albedo.json",        4, "materials.m.albedo: albedo must not be negative"},
  {"negative_emission.json",      3, "emission must not be negative"},
  {"negative_background.json",    2, "must not be negative"},
  {"eye_equals_target.json",      2, "same point"},
  {"up_parallel.json",            3, "camera.up: camera up is parallel"},
  {"up_zero.json",                3, "camera up must not be zero"},
  {"fov_zero.json",               3, "camera.fov: fov must be between 0 and 180"},
  {"fov_180.json",                3, "camera.fov: fov must be between 0 and 180"},
  {"zero_rotation_axis.json",     4, "rotation axis must not be zero"},
  {"rotate_wrong_length.json",    5, "transform.rotate: expected an array of 4 numbers"},
  {"zero_scale.json",             4, "scale must not be zero"},
  {"unknown_generator.json",      4, "unknown generator 'trefoil'"},
  {"knot_not_coprime.json",       4, "coprime"},
  {"knot_fractional_segments.json", 5, "shapes[0].generate.segments: expected an integer from 3 to 1048576"},
  {"knot_two_segments.json",      5, "shapes[0].generate.segments: expected an integer from 3 to 1048576"},
  // JSON referring to files
  {"missing_mesh_file.json",      3, "does-not-exist.obj: cannot open"},
  {"mesh_file_is_directory.json", 4, "is a directory"},
  {"mesh_unsupported_type.json",  4, "triangle.ply: no triangles (the file has no faces) (read as OBJ: a mesh file is an .obj, .gltf or .glb, by its extension)"},
  {"mesh_with_bad_obj.json",      4, "index_out_of_range.obj.txt:4: face vertex index 9 out of range"},
  // OBJ
  {"empty.obj",                   0, "no triangles"},
  {"no_faces.obj",                0, "no triangles"},
  {"only_degenerate.obj",         0, "no triangles"},
  {"binary_garbage.obj",          1, "binary data"},
  {"nan_vertex.obj",              2, "'nan' is not a finite number"},
  {"non_numeric_vertex.obj",      2, "'abc' is not a finite number"},
  {"vertex_overflow.obj",         2, "'1e39' is not a finite number"},
  {"vertex_missing_coordinate.obj", 2, "'v' needs 3 numbers"},
  {"normal_garbage_crlf.obj",     4, "'x' is not a finite number"},
  {"face_with_two_vertices.obj",  4, "at least 3 vertices"},
  {"face_with_too_many_corners.obj", 258, "a face with 256 vertices (at most 255 are supported)"},
  {"face_index_out_of_range.obj", 4, "face vertex index 4 out of range (3 defined so far)"},
  {"face_index_zero.obj",         5, "index 0"},
  {"negative_index_too_far.obj",  4, "face vertex index -4 out of range"},
  {"face_index_not_integer.obj",  4, "'1.5' is not an integer"},
  {"face_corner_malformed.obj",   4, "malformed face corner '1/1/1/1'"},
  {"normal_index_out_of_range.obj", 5, "face normal index 2 out of range"},
  {"texcoord_index_out_of_range.obj", 6, "face texture coordinate index 2 out of range"},
  {"bad_mtl.obj",                 1, "helpers/bad.mtl:3: Ks: expected 1 or 3 finite numbers"},
  // glTF (no lines: "FILE: reason")
  {"glb_truncated.glb",           0, "truncated .glb"},
  {"glb_wrong_magic.glb",         0, "wrong magic"},
  {"gltf_missing_bin.gltf",       0, "no-such.bin"},
  {"gltf_bad_data_uri.gltf",      0, "uri"},
  {"gltf_accessor_out_of_range.gltf", 0, "mesh 0 'tri' primitive 0: POSITION accessor 4 out of range"},
  {"gltf_view_past_buffer_end.gltf", 0, "bufferView 0: bytes 8 + 36 overlap the end of buffer 0 (36 bytes)"},
  {"gltf_accessor_past_view_end.gltf", 0, "accessor 0: 3 elements from byte 4 overlap the end of bufferView 0"},
  {"gltf_index_past_vertex_count.gltf", 0, "mesh 0 'tri' primitive 0: index 7 past the vertex count 3"},
  {"gltf_nonfinite_position.gltf", 0, "non-finite vertex position"},
  {"gltf_overflowing_matrix.gltf", 0, "node 0: non-finite transformed position"},
  {"gltf_cyclic_nodes.gltf",      0, "cyclic node graph"},
  {"gltf_required_extension.gltf", 0, "unsupported required extension 'KHR_draco_mesh_compression'"},
  {"mesh_with_bad_gltf.json",     4, "gltf_cyclic_nodes.gltf: cyclic node graph"},
};
// clang-format on

fs::path bad_dir() { return fs::path(PTVIEW_TEST_DATA) / "bad"; }

TEST(BadCorpus, EveryFileFailsWithItsPathLineAndReason) {
  for (const BadCase& c : kCases) {
    SCOPED_TRACE(c.file);
    std::string path = (bad_dir() / c.file).string();
    Result<Scene> r = load_scene(path);
    ASSERT_FALSE(r.ok()) << "loaded but should not";
    const std::string& msg = r.error();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    std::string prefix = c.line > 0 ? path + ":" + std::to_string(c.line) + ": " : path + ": ";
    EXPECT_TRUE(msg.starts_with(prefix)) << "expected prefix '" << prefix << "', got: " << msg;
    EXPECT_NE(msg.find(c.reason), std::string::npos) << "expected '" << c.reason << "' in: " << msg;
  }
}

TEST(BadCorpus, EveryBadSceneFileIsInTheTable) {
  std::set<std::string> listed;
  for (const BadCase& c : kCases) EXPECT_TRUE(listed.insert(c.file).second) << "listed twice: " << c.file;
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(bad_dir())) {
    std::string ext = e.path().extension().string();
    if (ext != ".json" && ext != ".obj" && ext != ".gltf" && ext != ".glb") continue;
    ++files;
    EXPECT_TRUE(listed.count(e.path().filename().string())) << "not in the table: " << e.path();
  }
  EXPECT_EQ(files, listed.size());
  EXPECT_GE(files, 25u);
}

TEST(BadCorpus, UppercaseExtensionsAreRecognised) {
  // The extension check is case-insensitive: a copy named .JSON / .OBJ is parsed (and fails the same way).
  fs::path dir = fs::temp_directory_path() / "ptview-test-bad-corpus-ext";
  fs::create_directories(dir);
  for (auto [from, to] : {std::pair{"fov_zero.json", "FOV.JSON"}, std::pair{"face_index_zero.obj", "ZERO.Obj"}}) {
    fs::copy_file(bad_dir() / from, dir / to, fs::copy_options::overwrite_existing);
    std::string path = (dir / to).string();
    Result<Scene> r = load_scene(path);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(r.error().starts_with(path + ":")) << r.error();
    EXPECT_EQ(r.error().find("unsupported"), std::string::npos) << r.error();
  }
  fs::remove_all(dir);
}

TEST(BadCorpus, UnreadablePathsAreOneLineErrorsWithoutHanging) {
  // Devices and directories are refused before reading (/dev/zero would never end).
  for (std::string p : {"/dev/zero", "/dev/zero.json", "/dev/null", "/nonexistent/a.json", "/nonexistent/b.obj"}) {
    Result<Scene> r = load_scene(p);
    ASSERT_FALSE(r.ok()) << p;
    EXPECT_TRUE(r.error().starts_with(p + ": ")) << r.error();
  }
  fs::path d = fs::temp_directory_path() / "ptview-test-dir-scene.json";
  fs::create_directories(d);
  Result<Scene> r = load_scene(d.string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), d.string() + ": cannot open: is a directory");
  fs::remove(d);
  Result<Scene> unsupported = load_scene((bad_dir() / "helpers" / "bad.mtl").string());
  ASSERT_FALSE(unsupported.ok());
  EXPECT_NE(unsupported.error().find("unsupported scene type '.mtl'"), std::string::npos) << unsupported.error();
}

}  // namespace
}  // namespace pt
