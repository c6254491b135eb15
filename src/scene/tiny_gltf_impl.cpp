/// The one translation unit that compiles tinygltf (Debian ships it header-only in practice; compiling it here,
/// rather than linking libtinygltf.so, puts it under our sanitizers and fuzzers). Image decoding and writing are
/// left out: load_gltf.cpp installs its own image callback (stb_image from libstb, only for a texture's mean colour).
/// TINYGLTF_NO_STB_IMAGE(_WRITE) are set for the whole scene library in CMakeLists.txt.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
