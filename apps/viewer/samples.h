// The viewer's sample browser: every scene file of a folder plus built-in samples made with the
// shared scene builders (inertia/world/builders.h), grouped as in Box2D's samples. Plain data
// and io::Scene values, no GL, so the list is testable headless.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "inertia/io/scene.h"
#include "inertia/world/world.h"

namespace inertia::viewer {

/// One entry of the sample browser.
struct Sample {
  std::string group;  ///< "Stacking", "Collision", "Contacts", "Particles", "Scenes", ...
  std::string name;   ///< Unique within its group.
  /// Makes the scene (plain data); io::instantiate() turns it into a World. May throw
  /// io::SceneError (a scene file) or InvalidArgument.
  std::function<io::Scene()> build;
  std::filesystem::path file{};  ///< The scene file, empty for a built-in sample.
  /// A built-in sample's controller, called before every physics step (an arm's inverse
  /// kinematics): it reads and drives the world as a user's code would. Empty for most.
  std::function<void(World&)> control{};
};

/// The built-in samples (Stacking, Collision, Contacts, Joints, Articulations), made by the
/// shared builders.
std::vector<Sample> builtinSamples();

/// One sample per *.json file of `dir` (not recursive), sorted by file name, named by the file's
/// stem. Files are not loaded here, only peeked at: one whose JSON has a non-empty
/// "particle_systems" goes to the group "Particles", else one with a non-empty "deformables" to
/// "Deformables", the others to "Scenes". A missing folder gives an empty list.
std::vector<Sample> sceneFileSamples(const std::filesystem::path& dir);

/// The scene files of `scenesDir` (when given) followed by the built-in samples.
std::vector<Sample> allSamples(const std::optional<std::filesystem::path>& scenesDir);

/// The index of the sample whose file is `file` (compared as canonical paths) or whose name
/// equals `name`, or nullopt.
std::optional<std::size_t> findSample(const std::vector<Sample>& samples,
                                      const std::string& nameOrFile);

/// The examples folder: `explicitDir` when given, else the first existing of `scenes/` next to
/// the executable's folder or one of its four parents (build trees are build/<name>/apps/inertia/)
/// and `sourceDir`/scenes. Nullopt when none exists.
std::optional<std::filesystem::path> findScenesDir(
    const std::optional<std::filesystem::path>& explicitDir,
    const std::filesystem::path& executable, const std::filesystem::path& sourceDir);

/// The groups of `samples` in first-appearance order.
std::vector<std::string> sampleGroups(const std::vector<Sample>& samples);

}  // namespace inertia::viewer
