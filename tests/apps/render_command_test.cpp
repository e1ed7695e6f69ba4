// `inertia render` end to end: images of the requested size that show the scene, a falling
// sphere that moves down the image, videos with the requested frame count, and bad input.
#include "render_command.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <vector>

#include "png_test_util.h"
#include "run_cli.h"

namespace inertia::test {
namespace {

// A red ball falling from y = 4 onto a ground plane, seen from the front.
const char* kFallingBall = R"({
  "world": {"dt": 0.01, "substeps": 2},
  "camera": {"position": [0, 2.5, 9], "target": [0, 2.5, 0], "fov": 45},
  "bodies": [
    {"name": "ground", "type": "static", "shapes": [{"type": "plane", "normal": [0, 1, 0], "offset": 0}]},
    {"name": "ball", "position": [0, 4, 0],
     "shapes": [{"type": "sphere", "radius": 0.5, "color": [0.9, 0.1, 0.1]}]}
  ]
})";

struct RenderedPng : test::PngImage {
  double lumaVariance() const {
    double sum = 0, sum2 = 0;
    const std::size_t n = rgb.size() / 3;
    for (std::size_t i = 0; i < n; ++i) {
      const double y = 0.299 * rgb[3 * i] + 0.587 * rgb[3 * i + 1] + 0.114 * rgb[3 * i + 2];
      sum += y;
      sum2 += y * y;
    }
    return sum2 / double(n) - (sum / double(n)) * (sum / double(n));
  }
  // Mean image row of the red pixels (r > 2 g, r > 2 b); -1 when none.
  double redRow(int* count = nullptr) const {
    double rows = 0;
    int n = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const std::uint8_t* p = at(x, y);
        if (p[0] > 60 && p[0] > 2 * p[1] && p[0] > 2 * p[2]) rows += y, ++n;
      }
    if (count) *count = n;
    return n ? rows / n : -1;
  }
};

// Frames reported by ffprobe after decoding the whole stream.
int ffprobeFrames(const std::string& file) {
  const std::string command =
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=nb_read_frames -of csv=p=0 " +
      file;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  int frames = -1;
  if (std::fscanf(pipe, "%d", &frames) != 1) frames = -1;
  pclose(pipe);
  return frames;
}

using Render = CliTest;

TEST_F(Render, PngHasTheRequestedSizeAndIsNotBlank) {
  const std::string scene = write("ball.json", kFallingBall);
  CliResult r = runCli("render " + scene + " --out " + path("f.png") + " --size 160x120 --time 0");
  ASSERT_EQ(r.code, 0) << r.output;
  RenderedPng png;
  ASSERT_TRUE(png.load(path("f.png")));
  EXPECT_EQ(png.width, 160);
  EXPECT_EQ(png.height, 120);
  // Sky, grey ground and a red ball: a blank or single-colour image has variance 0.
  EXPECT_GT(png.lumaVariance(), 100.0);
  int red = 0;
  png.redRow(&red);
  EXPECT_GT(red, 20);
}

// A built-in sample is rendered by its name (with its controller), when no file has that name.
TEST_F(Render, BuiltinSampleByName) {
  CliResult r = runCli("render \"Arm following a target\" -q --out " + path("arm.png") +
                       " --size 160x120 --time 0.5");
  ASSERT_EQ(r.code, 0) << r.output;
  RenderedPng png;
  ASSERT_TRUE(png.load(path("arm.png")));
  EXPECT_GT(png.lumaVariance(), 100.0);
  EXPECT_EQ(runCli("render \"No such sample\" -q --out " + path("x.png")).code, 2);
}

TEST_F(Render, FallingBallMovesDownTheImage) {
  const std::string scene = write("ball.json", kFallingBall);
  // y(t) = 4 - g t^2 / 2: 4 m at t = 0, 2.2 m at t = 0.6 s (before touching the ground).
  ASSERT_EQ(
      runCli("render " + scene + " -q --out " + path("a.png") + " --size 160x120 --time 0").code,
      0);
  ASSERT_EQ(
      runCli("render " + scene + " -q --out " + path("b.png") + " --size 160x120 --time 0.6").code,
      0);
  RenderedPng a, b;
  ASSERT_TRUE(a.load(path("a.png")));
  ASSERT_TRUE(b.load(path("b.png")));
  const double rowA = a.redRow(), rowB = b.redRow();
  ASSERT_GE(rowA, 0);
  ASSERT_GE(rowB, 0);
  // 1.8 m at 9 m with a 45 degree field of view is about 0.24 of the image height (29 rows).
  EXPECT_GT(rowB - rowA, 20) << rowA << " -> " << rowB;
  EXPECT_LT(rowB - rowA, 40) << rowA << " -> " << rowB;
}

TEST_F(Render, PngSequenceWritesOneFilePerFrame) {
  const std::string scene = write("ball.json", kFallingBall);
  CliResult r = runCli("render " + scene + " --out " + path("f_%03d.png") +
                       " --size 64x48 --duration 0.3 --fps 10");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : {"f_000.png", "f_001.png", "f_002.png"})
    EXPECT_TRUE(std::filesystem::exists(path(f))) << f;
  EXPECT_FALSE(std::filesystem::exists(path("f_003.png")));
}

TEST_F(Render, Mp4HasTheRequestedFrameCount) {
  const std::string scene = write("ball.json", kFallingBall);
  CliResult r = runCli("render " + scene + " --out " + path("clip.mp4") +
                       " --size 160x120 --duration 0.5 --fps 10");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(ffprobeFrames(path("clip.mp4")), 5);
}

TEST_F(Render, GifIsWritten) {
  const std::string scene = write("ball.json", kFallingBall);
  CliResult r = runCli("render " + scene + " --out " + path("clip.gif") +
                       " --size 80x60 --duration 0.3 --fps 10");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(ffprobeFrames(path("clip.gif")), 3);
}

TEST_F(Render, SceneWithoutCameraIsFramed) {
  // No camera: the default frames the ball (and the ground below it).
  const std::string scene = write("nocam.json", R"({
    "bodies": [{"type": "static", "shapes": [{"type": "plane"}]},
               {"position": [5, 3, -2], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5],
                                                    "color": [1, 0, 0]}]}]})");
  ASSERT_EQ(runCli("render " + scene + " --out " + path("f.png") + " --size 96x72 --time 0").code,
            0);
  RenderedPng png;
  ASSERT_TRUE(png.load(path("f.png")));
  int red = 0;
  png.redRow(&red);
  EXPECT_GT(red, 30);
}

TEST_F(Render, BadInputIsExitCode2) {
  const std::string scene = write("ball.json", kFallingBall);
  struct Case {
    std::string args, env, message;
  };
  const std::vector<Case> cases = {
      {"--out " + path("f.png") + " --size 160", "", "--size"},
      {"--out " + path("f.png") + " --size 0x10", "", "--size"},
      {"--out " + path("f.png") + " --size 160x120x3", "", "--size"},
      {"--out " + path("f.avi"), "", "unknown output type"},
      {"--out " + path("f_%d_%d.png"), "", "pattern"},
      {"--out " + path("f.mp4") + " --size 161x120", "", "even"},
      {"--out " + path("f.mp4") + " --size 160x120", "PATH=/nonexistent", "ffmpeg"},
      {"--out " + path("f.mp4") + " --time 1", "", "--time"},
      {"--out " + path("f.png") + " --fps 0", "", "--fps"},
      {"--out " + path("no/such/dir/f.png") + " --size 16x16 --time 0", "", "cannot be written"},
  };
  for (const Case& c : cases) {
    CliResult r = runCli("render " + scene + " " + c.args, c.env);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
  }
  CliResult missing = runCli("render " + path("none.json") + " --out " + path("f.png"));
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.output.find("no such file"), std::string::npos) << missing.output;
  const std::string badCamera =
      write("cam.json", R"({"camera": {"position": [0, 1, 5], "fov": 200}})");
  CliResult cam = runCli("render " + badCamera + " --out " + path("f.png"));
  EXPECT_EQ(cam.code, 2);
  EXPECT_NE(cam.output.find("/camera/fov"), std::string::npos) << cam.output;
}

}  // namespace
}  // namespace inertia::test
