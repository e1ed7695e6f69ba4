// A headless OpenGL 3.3 core context from EGL, and reading back an offscreen target.
#include "offscreen.h"

#include <gtest/gtest.h>

namespace inertia::viewer {
namespace {

TEST(Offscreen, EglGivesACoreContextWithoutADisplay) {
  EglContext context;
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_GE(major * 10 + minor, 33);
  EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
  EXPECT_FALSE(context.renderer().empty());
  EXPECT_FALSE(context.platform().empty());
}

TEST(Offscreen, ReadBackIsTopDownRgb) {
  EglContext context;
  for (int samples : {1, 4}) {
    OffscreenTarget target(8, 6, samples);
    target.bind();
    glClearColor(1, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    // The top two rows (GL's y = 4, 5) green.
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 4, 8, 2);
    glClearColor(0, 1, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    const std::vector<std::uint8_t> rgb = target.readRgb();
    ASSERT_EQ(rgb.size(), 3u * 8 * 6);
    for (int y = 0; y < 6; ++y) {
      const std::uint8_t* p = &rgb[3 * (y * 8 + 3)];
      const bool green = y < 2;
      EXPECT_EQ(p[0], green ? 0 : 255) << "row " << y << " samples " << samples;
      EXPECT_EQ(p[1], green ? 255 : 0) << "row " << y << " samples " << samples;
      EXPECT_EQ(p[2], 0);
    }
  }
  EXPECT_THROW(OffscreenTarget(0, 4), GlError);
}

}  // namespace
}  // namespace inertia::viewer
