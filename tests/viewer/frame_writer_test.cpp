// Output kinds from paths, sequence names, PNG round trip (stb), and ffmpeg encoding.
#include "frame_writer.h"

#include <gtest/gtest.h>
#include <stb_image.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

namespace inertia::viewer {
namespace {

namespace fs = std::filesystem;

fs::path tempDir(const char* name) {
  fs::path d = fs::temp_directory_path() / (std::string("inertia_frame_writer_") + name);
  fs::create_directories(d);
  return d;
}

std::vector<std::uint8_t> gradient(int w, int h, int shift = 0) {
  std::vector<std::uint8_t> rgb(3 * std::size_t(w) * std::size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &rgb[3 * (std::size_t(y) * w + x)];
      p[0] = std::uint8_t((x * 255) / w + shift);
      p[1] = std::uint8_t((y * 255) / h);
      p[2] = 128;
    }
  return rgb;
}

TEST(FrameWriter, OutputKindFollowsTheExtension) {
  EXPECT_EQ(outputKind("a/b.png"), OutputKind::Png);
  EXPECT_EQ(outputKind("a/B.PNG"), OutputKind::Png);
  EXPECT_EQ(outputKind("f_%04d.png"), OutputKind::PngSequence);
  EXPECT_EQ(outputKind("f%d.png"), OutputKind::PngSequence);
  EXPECT_EQ(outputKind("100%%_%03d.png"), OutputKind::PngSequence);
  EXPECT_EQ(outputKind("clip.mp4"), OutputKind::Mp4);
  EXPECT_EQ(outputKind("clip.gif"), OutputKind::Gif);
  EXPECT_THROW(outputKind("clip.avi"), OutputError);
  EXPECT_THROW(outputKind("noextension"), OutputError);
  EXPECT_THROW(outputKind("f_%s.png"), OutputError);
  EXPECT_THROW(outputKind("f_%d_%d.png"), OutputError);
  EXPECT_THROW(outputKind("f_%d.mp4"), OutputError);
}

TEST(FrameWriter, SequencePathNumbersFrames) {
  EXPECT_EQ(sequencePath("out/f_%04d.png", 7), "out/f_0007.png");
  EXPECT_EQ(sequencePath("f%d.png", 12345), "f12345.png");
  EXPECT_EQ(sequencePath("100%%_%03d.png", 5), "100%_005.png");
}

TEST(FrameWriter, PngRoundTrips) {
  const fs::path file = tempDir("png") / "g.png";
  const auto rgb = gradient(37, 21);
  writePng(file.string(), 37, 21, rgb);
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(file.string().c_str(), &w, &h, &n, 3);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 37);
  EXPECT_EQ(h, 21);
  EXPECT_TRUE(std::equal(rgb.begin(), rgb.end(), data));
  stbi_image_free(data);
  EXPECT_THROW(writePng((tempDir("png") / "missing" / "x.png").string(), 37, 21, rgb), OutputError);
  EXPECT_THROW(writePng(file.string(), 36, 21, rgb), OutputError);
  fs::remove_all(tempDir("png"));
}

TEST(FrameWriter, Mp4HasEveryFrame) {
  const fs::path file = tempDir("mp4") / "clip.mp4";
  VideoEncoder video(file.string(), OutputKind::Mp4, 64, 48, 10);
  for (int k = 0; k < 7; ++k) video.write(gradient(64, 48, 20 * k));
  video.finish();
  const std::string command =
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=nb_read_frames,width,height -of csv=p=0 " +
      file.string();
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char line[128] = {};
  ASSERT_NE(std::fgets(line, sizeof line, pipe), nullptr);
  pclose(pipe);
  EXPECT_EQ(std::string(line), "64,48,7\n");
  fs::remove_all(tempDir("mp4"));
}

TEST(FrameWriter, VideoWithoutFfmpegIsAnError) {
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  setenv("PATH", "/nonexistent", 1);
  EXPECT_FALSE(findExecutable("ffmpeg"));
  EXPECT_THROW(VideoEncoder("x.mp4", OutputKind::Mp4, 64, 48, 10), OutputError);
  setenv("PATH", saved.c_str(), 1);
  EXPECT_TRUE(findExecutable("ffmpeg"));
}

}  // namespace
}  // namespace inertia::viewer
