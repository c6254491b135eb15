// Every malformed file in tests/data/bad gives an error that starts with the file's path and, where the problem
// sits on a line, names that line (table: tests/data/bad/EXPECTED_LINES.txt).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/load.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

TEST(BadCorpus, EveryFileFailsWithItsPathAndLine) {
  fs::path dir = fs::path(PTVIEW_TEST_DATA) / "bad";
  std::ifstream table(dir / "EXPECTED_LINES.txt");
  std::string line;
  int checked = 0;
  while (std::getline(table, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    std::string name;
    int expected_line = 0;
    in >> name >> expected_line;
    std::string path = (dir / name).string();
    Result<Scene> r = load_scene(path);
    ASSERT_FALSE(r.ok()) << name << " loaded but should not";
    const std::string& msg = r.error();
    EXPECT_EQ(msg.rfind(path, 0), 0u) << name << ": " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << name << ": " << msg;
    if (expected_line > 0) {
      std::string located = path + ":" + std::to_string(expected_line) + ":";
      EXPECT_EQ(msg.rfind(located, 0), 0u) << name << ": expected line " << expected_line << ", got: " << msg;
    }
    ++checked;
  }
  EXPECT_GE(checked, 30);
  // Every bad scene file is in the table, so none escapes the line check.
  int files = 0;
  for (auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".json" || e.path().extension() == ".obj") ++files;
  EXPECT_EQ(files, checked);
}

TEST(BadCorpus, NestedObjErrorsNameBothFiles) {
  std::string path = (fs::path(PTVIEW_TEST_DATA) / "bad" / "mesh_with_bad_obj.json").string();
  Result<Scene> r = load_scene(path);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("index_out_of_range.obj.txt:4:"), std::string::npos) << r.error();
}

TEST(BadCorpus, NonRegularFilesAreRefusedWithoutHanging) {
  for (const char* p : {"/dev/zero", "/dev/null", "/tmp"}) {
    for (const char* ext : {"", ".json", ".obj"}) {
      (void)ext;
    }
    Result<Scene> r = load_scene(p);
    EXPECT_FALSE(r.ok()) << p;
  }
  // A directory named like a scene.
  fs::path d = fs::temp_directory_path() / "ptview-dir-scene.json";
  fs::create_directories(d);
  Result<Scene> r = load_scene(d.string());
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error().find("directory"), std::string::npos) << r.error();
  fs::remove(d);
}

}  // namespace
}  // namespace pt
