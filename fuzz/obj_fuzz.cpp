// The OBJ loader on arbitrary text: ObjError (naming the file and line) or a mesh of finite
// vertices with in-range triangles.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_input.h"
#include "inertia/io/obj.h"

using namespace inertia;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // loadObj reads a file: one per process, rewritten for each input.
  static const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                            ("inertia_fuzz_" + std::to_string(getpid()) + ".obj");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  try {
    const TriangleMesh mesh = io::loadObj(file);
    for (const Vec3& v : mesh.vertices()) INERTIA_FUZZ_FINITE(v);
    for (const Triangle& t : mesh.triangles())
      for (std::uint32_t i : t)
        if (i >= mesh.vertices().size()) std::abort();
  } catch (const io::ObjError&) {
  }
  return 0;
}
