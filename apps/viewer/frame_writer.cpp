#include "frame_writer.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stb_image_write.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

extern char** environ;

namespace inertia::viewer {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

// True when `name` holds exactly one printf integer conversion (%d with optional flags "0" and
// width) and no other '%' except "%%".
bool isSequencePattern(const std::string& name, bool& hasPercent) {
  int conversions = 0;
  hasPercent = false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (name[i] != '%') continue;
    hasPercent = true;
    if (i + 1 < name.size() && name[i + 1] == '%') {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < name.size() && std::isdigit(static_cast<unsigned char>(name[j]))) ++j;
    if (j >= name.size() || name[j] != 'd' || j - i > 4) return false;
    ++conversions;
    i = j;
  }
  return conversions == 1;
}

}  // namespace

OutputKind outputKind(const std::string& path) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  const std::string name = std::filesystem::path(path).filename().string();
  bool hasPercent = false;
  const bool sequence = isSequencePattern(name, hasPercent);
  if (ext == ".png") {
    if (sequence) return OutputKind::PngSequence;
    if (hasPercent)
      throw OutputError(
          path + ": a frame pattern needs exactly one integer conversion, e.g. frame_%04d.png");
    return OutputKind::Png;
  }
  if (hasPercent) throw OutputError(path + ": frame patterns are for .png sequences only");
  if (ext == ".mp4") return OutputKind::Mp4;
  if (ext == ".gif") return OutputKind::Gif;
  throw OutputError(path + ": unknown output type \"" + ext +
                    "\"; expected .png, a .png pattern such as frame_%04d.png, .mp4 or .gif");
}

std::string sequencePath(const std::string& pattern, std::int64_t index) {
  // Replace the single integer conversion; "%%" becomes "%".
  std::string out;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out += '%';
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < pattern.size() && pattern[j] != 'd') ++j;
    char buffer[32];
    // Appended piecewise: "%" + substr(...) trips GCC 12's false -Wrestrict at -O3.
    std::string spec = "%";
    spec.append(pattern, i + 1, j - i - 1);
    spec += "lld";
    std::snprintf(buffer, sizeof buffer, spec.c_str(), static_cast<long long>(index));
    out += buffer;
    i = j;
  }
  return out;
}

void writePng(const std::string& path, int width, int height, std::span<const std::uint8_t> rgb) {
  if (rgb.size() != 3 * std::size_t(width) * std::size_t(height))
    throw OutputError(path + ": image buffer does not match its size");
  if (!stbi_write_png(path.c_str(), width, height, 3, rgb.data(), 3 * width))
    throw OutputError(path + ": cannot be written");
}

std::optional<std::string> findExecutable(const std::string& name) {
  const char* env = std::getenv("PATH");
  if (!env) return std::nullopt;
  const std::string path = env;
  std::size_t start = 0;
  while (start <= path.size()) {
    std::size_t end = path.find(':', start);
    if (end == std::string::npos) end = path.size();
    const std::string dir = path.substr(start, end - start);
    if (!dir.empty()) {
      const std::string candidate = dir + "/" + name;
      if (access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    start = end + 1;
  }
  return std::nullopt;
}

VideoEncoder::VideoEncoder(const std::string& path, OutputKind kind, int width, int height,
                           double fps)
    : path_(path), frameBytes_(3 * std::size_t(width) * std::size_t(height)) {
  if (kind != OutputKind::Mp4 && kind != OutputKind::Gif)
    throw OutputError(path + ": not a video output");
  const std::optional<std::string> ffmpeg = findExecutable("ffmpeg");
  if (!ffmpeg)
    throw OutputError(
        path + ": writing video needs ffmpeg, which is not on PATH (install the ffmpeg package)");
  char size[32], rate[32];
  std::snprintf(size, sizeof size, "%dx%d", width, height);
  std::snprintf(rate, sizeof rate, "%.9g", fps);
  std::vector<std::string> args = {
      "ffmpeg",   "-hide_banner", "-loglevel", "error", "-nostdin",   "-y", "-f", "rawvideo",
      "-pix_fmt", "rgb24",        "-s",        size,    "-framerate", rate, "-i", "-"};
  if (kind == OutputKind::Mp4) {
    args.insert(args.end(), {"-c:v", "libx264", "-preset", "medium", "-crf", "20", "-pix_fmt",
                             "yuv420p", "-movflags", "+faststart"});
  } else {
    args.insert(args.end(), {"-vf", "split[a][b];[a]palettegen[p];[b][p]paletteuse", "-loop", "0"});
  }
  args.push_back(path);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw OutputError(path + ": cannot create a pipe to ffmpeg");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
  const int rc = posix_spawn(&pid_, ffmpeg->c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[0]);
  if (rc != 0) {
    close(fds[1]);
    pid_ = -1;
    throw OutputError(path + ": cannot start ffmpeg: " + std::strerror(rc));
  }
  pipe_ = fds[1];
  // A dying ffmpeg must give EPIPE on write, not kill this process.
  signal(SIGPIPE, SIG_IGN);
}

VideoEncoder::~VideoEncoder() {
  if (pipe_ >= 0) close(pipe_);
  if (pid_ > 0) {
    int status = 0;
    waitpid(pid_, &status, 0);
  }
}

void VideoEncoder::write(std::span<const std::uint8_t> rgb) {
  if (rgb.size() != frameBytes_)
    throw OutputError(path_ + ": frame size does not match the video's");
  const std::uint8_t* p = rgb.data();
  std::size_t left = rgb.size();
  while (left > 0) {
    const ssize_t n = ::write(pipe_, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw OutputError(path_ + ": ffmpeg stopped reading frames (" + std::strerror(errno) + ")");
    }
    p += n;
    left -= std::size_t(n);
  }
}

void VideoEncoder::finish() {
  if (pipe_ >= 0) close(pipe_);
  pipe_ = -1;
  if (pid_ <= 0) return;
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw OutputError(
        path_ + ": ffmpeg failed (exit status " +
        std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)) + ")");
}

}  // namespace inertia::viewer
