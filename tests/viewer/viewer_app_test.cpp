// The interactive viewer without a display: it says so and returns 2, never crashes; bad
// input is reported the same way before any window is opened.
#include "viewer_app.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <string>

namespace inertia::viewer {
namespace {

// Unsets DISPLAY and WAYLAND_DISPLAY for one test, restoring them after.
class NoDisplay : public testing::Test {
 protected:
  void SetUp() override {
    for (int i = 0; i < 2; ++i) {
      if (const char* v = std::getenv(kNames[i])) saved_[i] = v;
      unsetenv(kNames[i]);
    }
  }
  void TearDown() override {
    for (int i = 0; i < 2; ++i)
      if (saved_[i]) setenv(kNames[i], saved_[i]->c_str(), 1);
  }
  static constexpr const char* kNames[2] = {"DISPLAY", "WAYLAND_DISPLAY"};
  std::optional<std::string> saved_[2];
};

TEST_F(NoDisplay, ProblemIsNamed) {
  const std::string problem = displayProblem();
  EXPECT_NE(problem.find("DISPLAY"), std::string::npos);
  EXPECT_NE(problem.find("WAYLAND_DISPLAY"), std::string::npos);
  setenv("WAYLAND_DISPLAY", "wayland-0", 1);
  EXPECT_EQ(displayProblem(), "");
  unsetenv("WAYLAND_DISPLAY");
  setenv("DISPLAY", "", 1);  // set but empty names no display
  EXPECT_NE(displayProblem(), "");
}

TEST_F(NoDisplay, RunReturnsTwo) {
  testing::internal::CaptureStderr();
  EXPECT_EQ(runViewer({.frames = 1}), 2);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("no display"), std::string::npos) << err;
}

TEST_F(NoDisplay, BadSceneIsReportedFirst) {
  testing::internal::CaptureStderr();
  EXPECT_EQ(runViewer({.scene = "/nonexistent/scene.json", .frames = 1}), 2);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("/nonexistent/scene.json"), std::string::npos) << err;
  EXPECT_EQ(err.find("no display"), std::string::npos) << err;
}

}  // namespace
}  // namespace inertia::viewer
