#include <cstdio>
#include <exception>
#include <new>

#include "app/app.h"

int main(int argc, char** argv) {
  try {
    return pt::run_app(argc, argv);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "ptview: error: out of memory\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ptview: error: %s\n", e.what());
  }
  return 2;
}
