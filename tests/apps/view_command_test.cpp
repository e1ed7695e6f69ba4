// `inertia view` end to end: without a display it exits 2 naming the problem; bad options
// exit 2; under Xvfb (when xvfb-run is installed) it runs frames of a scene and writes a
// screenshot that shows it.
#include "view_command.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

#include "png_test_util.h"
#include "run_cli.h"

namespace inertia::test {
namespace {

const std::string kNoDisplay = "env -u DISPLAY -u WAYLAND_DISPLAY";

std::string scene(const std::string& name) {
  const char* root = std::getenv("INERTIA_SOURCE_DIR");
  return std::string(root ? root : ".") + "/scenes/" + name;
}

struct ScreenshotPng : test::PngImage {
  // Pixels in [x0, x1) x [y0, y1) whose channels spread by more than 60 (coloured boxes, not
  // the grey ground, the pale sky or the dark panel).
  int colourful(int x0, int y0, int x1, int y1) const {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const std::uint8_t* p = at(x, y);
        const int hi = std::max({p[0], p[1], p[2]}), lo = std::min({p[0], p[1], p[2]});
        n += hi - lo > 60;
      }
    return n;
  }
};

using ViewCommand = CliTest;

TEST_F(ViewCommand, NoDisplayExitsTwoNamingTheProblem) {
  const CliResult r = runCli("view " + scene("pyramid.json") + " --frames 1", kNoDisplay);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("DISPLAY"), std::string::npos) << r.output;
  // Without a scene too (the sample browser alone).
  EXPECT_EQ(runCli("view", kNoDisplay).code, 2);
}

TEST_F(ViewCommand, UnreachableDisplayExitsTwo) {
  const CliResult r = runCli("view --frames 1", "env -u WAYLAND_DISPLAY DISPLAY=:9876");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("cannot open the display"), std::string::npos) << r.output;
}

TEST_F(ViewCommand, HelpDocumentsView) {
  const CliResult top = runCli("--help");
  EXPECT_EQ(top.code, 0);
  EXPECT_NE(top.output.find("view"), std::string::npos) << top.output;
  const CliResult help = runCli("view --help");
  EXPECT_EQ(help.code, 0);
  for (const char* option : {"--frames", "--screenshot", "--scenes", "--size", "--no-panel"})
    EXPECT_NE(help.output.find(option), std::string::npos) << option;
}

TEST_F(ViewCommand, BadInputExitsTwo) {
  const std::string pyramid = scene("pyramid.json");
  struct Case {
    std::string args, says;
  };
  for (const Case& c : {Case{"view " + pyramid + " --size 0x10", "--size"},
                        Case{"view " + pyramid + " --screenshot out.gif", "--screenshot"},
                        Case{"view --scenes /nonexistent/dir", "/nonexistent/dir"},
                        Case{"view /nonexistent/scene.json", "/nonexistent/scene.json"},
                        Case{"view " + write("bad.json", R"({"world": {"dt": -1}})"), "/world/dt"},
                        Case{"view " + pyramid + " --frames 0", "--frames"}}) {
    const CliResult r = runCli(c.args, kNoDisplay);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
  }
}

// Under a virtual X server: 30 frames of the pyramid, the last one written as PNG.
TEST_F(ViewCommand, ScreenshotUnderXvfbShowsTheScene) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1 && command -v xauth > /dev/null 2>&1"))
    FAIL() << "xvfb-run or xauth is not installed: run scripts/setup, which installs both";
  const std::string xvfb = "xvfb-run -a -s '-screen 0 1024x768x24'";
  const std::string shot = path("view.png");
  const CliResult r = runCli("view " + scene("pyramid.json") +
                                 " --frames 30 --size 320x240 --no-panel --screenshot " + shot,
                             xvfb);
  ASSERT_EQ(r.code, 0) << r.output;
  ScreenshotPng png;
  ASSERT_TRUE(png.load(shot)) << r.output;
  EXPECT_EQ(png.width, 320);
  EXPECT_EQ(png.height, 240);
  // The pyramid's coloured boxes fill the middle of the image; the sky above is pale.
  EXPECT_GT(png.colourful(120, 60, 200, 180), 2000);
  const std::uint8_t* sky = png.at(160, 3);
  EXPECT_GT(sky[2], 150);
  EXPECT_GT(sky[2], sky[0]);

  // With the panel: the same frame plus the dark panel at the top left.
  const std::string withPanel = path("panel.png");
  ASSERT_EQ(runCli("view " + scene("pyramid.json") + " --frames 2 --size 320x240 --screenshot " +
                       withPanel,
                   xvfb)
                .code,
            0);
  ScreenshotPng panel;
  ASSERT_TRUE(panel.load(withPanel));
  const std::uint8_t* p = panel.at(40, 40);
  EXPECT_LT(int(p[0]) + p[1] + p[2], 200) << "panel not drawn";
}

}  // namespace
}  // namespace inertia::test
