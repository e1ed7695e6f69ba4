// Helpers shared by the io layer's tests of scene-file errors.
#pragma once

#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "inertia/io/scene.h"

namespace inertia::test {

/// The error parseScene throws for `text`; a test failure when it throws none.
inline io::SceneError errorOf(const std::string& text) {
  try {
    io::parseScene(text, "test.json");
  } catch (const io::SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for: " << text;
  return io::SceneError("", "", "");
}

/// A bad scene file and what its error must say: a parameter of the BadScene, BadJoint and
/// BadArticulation tests.
struct BadCase {
  const char* text;
  const char* pointer;  // expected JSON pointer
  const char* words;    // expected in the reason
};

// GoogleTest shows a case by the pointer it expects, not by the struct's bytes (addresses, which
// changed CTest's names of these cases from build to build).
inline void PrintTo(const BadCase& c, std::ostream* out) { *out << c.pointer; }

}  // namespace inertia::test
