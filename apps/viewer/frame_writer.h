// Writing rendered frames: PNG files (stb_image_write), numbered PNG sequences, and MP4 or GIF
// videos encoded by an `ffmpeg` process fed raw RGB frames through a pipe.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

namespace inertia::viewer {

/// What an output path asks for, from its extension (case-insensitive) and pattern.
enum class OutputKind {
  Png,          ///< "frame.png": one image.
  PngSequence,  ///< "frame_%04d.png": one image per frame, numbered from 0.
  Mp4,          ///< H.264 (libx264, yuv420p).
  Gif,          ///< Palette generated from the whole clip (palettegen / paletteuse).
};

/// A bad output path or a failed write. what() says what is wrong.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The kind of `path`. Throws OutputError for an unknown extension, or a pattern that is not
/// exactly one integer conversion (%d, %04d, ...) in a .png name.
OutputKind outputKind(const std::string& path);

/// The path of frame `index` of a sequence pattern ("out/f_%04d.png", 7 -> "out/f_0007.png").
std::string sequencePath(const std::string& pattern, std::int64_t index);

/// Writes an RGB image (rows from the top, 3 * width * height bytes) as PNG. Throws OutputError.
void writePng(const std::string& path, int width, int height, std::span<const std::uint8_t> rgb);

/// The full path of an executable found on PATH, or nullopt.
std::optional<std::string> findExecutable(const std::string& name);

/// An ffmpeg process encoding frames of a fixed size into an MP4 or a GIF. Throws OutputError
/// when ffmpeg is not on PATH or cannot be started, and from write() / finish() when it fails.
class VideoEncoder {
 public:
  VideoEncoder(const std::string& path, OutputKind kind, int width, int height, double fps);
  ~VideoEncoder();  ///< Stops an unfinished encoding.
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  void write(std::span<const std::uint8_t> rgb);
  /// Closes the pipe and waits for ffmpeg; throws OutputError when it failed.
  void finish();

 private:
  std::string path_{};
  std::size_t frameBytes_ = 0;
  int pipe_ = -1;
  pid_t pid_ = -1;
};

}  // namespace inertia::viewer
