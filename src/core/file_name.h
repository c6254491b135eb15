#pragma once
/// A file's type by its name: the one definition shared by the scene loaders, the image reader and writers and the
/// command line, so that "scene.OBJ", "out.Png" and "ref.EXR" mean the same everywhere.
#include <cctype>
#include <filesystem>
#include <string>

namespace pt {

/// The extension of the path's file name, lower case, with its dot; "" if it has none. As std::filesystem defines
/// it: a dot in a folder name does not count, and neither does a file name's leading dot (".hidden").
inline std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace pt
