// A separate project using the installed package.
#include <cstdio>

#include <inertia/inertia.h>

int main() {
  inertia::World world({.gravity = {0, -9.81f, 0}, .dt = 1.0f / 60});
  for (int i = 0; i < 60; ++i) world.step(world.settings().dt);
  std::printf("consumer: %lld steps, t = %.3f s\n", (long long)world.stepCount(), world.time());
  return 0;
}
