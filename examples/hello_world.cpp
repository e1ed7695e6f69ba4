// The smallest Inertia program: a world stepped at a fixed rate for ten seconds of frames.
#include <cstdio>

#include <inertia/inertia.h>

int main() {
  inertia::World world({.gravity = {0, -9.81f, 0}, .dt = 1.0f / 60, .substeps = 4});
  for (int frame = 0; frame < 600; ++frame) world.advance(1.0f / 60);  // fixed-step accumulator
  std::printf("simulated %.3f s in %lld steps\n", world.time(), (long long)world.stepCount());
  return world.time() > 9.9 ? 0 : 1;
}
