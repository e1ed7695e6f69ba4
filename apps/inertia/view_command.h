// `inertia view`: the interactive viewer (apps/viewer/viewer_app.h) from the command line:
// finds the scenes folder, checks the options and reports a missing display with exit code 2.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace inertia::app {

struct ViewOptions {
  std::optional<std::string> scene{};      ///< A scene file or a sample name to open first.
  std::optional<std::string> scenesDir{};  ///< --scenes: the folder listed in the browser.
  std::string size = "1280x720";           ///< Window size WxH.
  std::int64_t frames = 0;                 ///< > 0: run this many frames and exit.
  std::string screenshot{};                ///< PNG of the last frame.
  std::optional<int> threads{};            ///< Overrides the scenes' world.threads.
  bool noPanel = false;                    ///< Start with the panel hidden.
};

int viewScene(const ViewOptions& options);

}  // namespace inertia::app
