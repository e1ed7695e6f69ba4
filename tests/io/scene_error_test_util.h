// Helpers shared by the io layer's tests of scene-file errors.
#pragma once

#include <gtest/gtest.h>

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

}  // namespace inertia::test
