// The scene loader on arbitrary bytes, as `inertia validate` reads a file: parse and check,
// then build the world. Bad input must give SceneError (file, JSON pointer, reason) or
// InvalidArgument (the API's refusal), never a crash, a hang or another exception.
#include <string>

#include "fuzz_input.h"
#include "inertia/core/error.h"
#include "inertia/io/scene.h"
#include "inertia/world/world.h"

using namespace inertia;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const io::Scene scene = io::parseScene(text, "fuzz.json");
    // Generators may ask for very many bodies; building those is valid but slow, not a finding.
    if (scene.bodies.size() > 2000) return 0;
    (void)io::instantiate(scene);
  } catch (const io::SceneError&) {
  } catch (const InvalidArgument&) {
  }
  return 0;
}
