// Checked reading of JSON values: every failure names the file and the JSON pointer.
// Private to the io layer; each section of the scene loader reads through it.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>

#include "inertia/core/error.h"
#include "inertia/core/types.h"
#include "inertia/io/scene.h"

namespace inertia::io::detail {

using Json = nlohmann::json;
using Pointer = nlohmann::json::json_pointer;

/// A JSON value together with where it is (file and pointer).
class Node {
 public:
  Node(const Json& value, Pointer pointer, const std::string& file)
      : value_(&value), pointer_(std::move(pointer)), file_(&file) {}

  const Json& json() const { return *value_; }
  const Pointer& pointer() const { return pointer_; }
  /// The file the value was read from (as named to the loader).
  const std::string& file() const { return *file_; }

  [[noreturn]] void fail(const std::string& reason) const;

  // Objects.
  /// Fails unless this is an object whose keys are all in `allowed` (naming the first stranger).
  void requireObject(std::span<const std::string_view> allowed) const;
  void requireObject(std::initializer_list<std::string_view> allowed) const {
    requireObject(std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  bool has(std::string_view key) const;
  /// The member `key`; fails if it is missing.
  Node at(std::string_view key) const;

  // Arrays.
  std::size_t requireArray() const;  ///< Fails unless an array; returns its size.
  Node at(std::size_t index) const;

  // Scalars: each fails on the wrong type, a non-finite number or a value out of range.
  std::string string() const;
  /// A file path: a non-empty string, relative to the directory of the file this was read
  /// from unless absolute (DESIGN.md section 4). `what` names the file in the message.
  std::filesystem::path path(const char* what) const;
  bool boolean() const;
  double number() const;
  /// A number in [lo, hi]; with `openLo`, lo itself is excluded (for "must be > 0").
  double number(double lo, double hi, bool openLo = false) const;
  long long integer(long long lo, long long hi) const;
  Vec3 vec3() const;
  /// A unit quaternion [w, x, y, z]; fails if its norm is off 1 by more than 1e-3, then normalises.
  Quat quaternion() const;

 private:
  const Json* value_;
  Pointer pointer_;
  const std::string* file_;
};

/// A short name of a JSON value's type for messages ("a string", "an array", ...).
std::string typeName(const Json& j);

/// f(), with the library's own refusal (InvalidArgument, from a settings check) turned into a
/// failure at `n`, so that it names the file and the JSON pointer.
template <class F>
auto checked(const Node& n, F&& f) {
  try {
    return f();
  } catch (const InvalidArgument& e) {
    n.fail(e.what());
  }
}

}  // namespace inertia::io::detail
