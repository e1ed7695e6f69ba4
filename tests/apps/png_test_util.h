// Shared by the end-to-end image tests: a PNG read back into 8-bit RGB (stb_image).
#pragma once

#include <stb_image.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace inertia::test {

struct PngImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  /// Reads `file`; false (and unchanged pixels) when it is not a readable image.
  bool load(const std::string& file) {
    int n = 0;
    unsigned char* data = stbi_load(file.c_str(), &width, &height, &n, 3);
    if (!data) return false;
    rgb.assign(data, data + 3 * std::size_t(width) * std::size_t(height));
    stbi_image_free(data);
    return true;
  }
  /// The pixel at column x, row y (from the top).
  const std::uint8_t* at(int x, int y) const { return &rgb[3 * (std::size_t(y) * width + x)]; }
};

}  // namespace inertia::test
