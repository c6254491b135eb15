// lower_extension decides every file type by name (scenes, meshes, images, references): one definition, so these
// cases hold for the loaders, the image writers and the command line alike.
#include <gtest/gtest.h>

#include "core/file_name.h"

namespace pt {
namespace {

TEST(FileName, TheExtensionIsLowerCaseWithItsDot) {
  EXPECT_EQ(lower_extension("scene.json"), ".json");
  EXPECT_EQ(lower_extension("models/Bunny.OBJ"), ".obj");
  EXPECT_EQ(lower_extension("out.Png"), ".png");
  EXPECT_EQ(lower_extension("/abs/path/ref.EXR"), ".exr");
}

TEST(FileName, OnlyTheLastDotOfTheFileNameCounts) {
  EXPECT_EQ(lower_extension("archive.tar.GZ"), ".gz");
  EXPECT_EQ(lower_extension("scene.v2/mesh"), "");  // a dot in a folder name is not the file's
  EXPECT_EQ(lower_extension("scene.v2/mesh.glb"), ".glb");
  EXPECT_EQ(lower_extension("noextension"), "");
  EXPECT_EQ(lower_extension("dir/.hidden"), "");  // a leading dot names a hidden file, not a type
  EXPECT_EQ(lower_extension("trailing."), ".");
  EXPECT_EQ(lower_extension(""), "");
}

}  // namespace
}  // namespace pt
