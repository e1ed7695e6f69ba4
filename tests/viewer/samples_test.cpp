// The viewer's sample list: every scene file of scenes/ is in it, built-in samples come from
// the shared builders, and every sample builds and runs 60 frames headless with finite state.
#include "samples.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

#include "inertia/world/builders.h"
#include "playback.h"

namespace inertia::viewer {
namespace {

namespace fs = std::filesystem;

fs::path scenesDir() {
  const char* root = std::getenv("INERTIA_SOURCE_DIR");
  return fs::path(root ? root : ".") / "scenes";
}

// Runs 60 frames of 1/60 s and checks every body's state and particle is finite.
void runSixtyFrames(const Sample& sample) {
  SCOPED_TRACE(sample.group + "/" + sample.name);
  Playback playback(sample.build());
  int steps = 0;
  for (int frame = 0; frame < 60; ++frame) steps += playback.frame(1.0 / 60);
  const World& world = playback.world();
  // 1 s of real time at the scene's fixed step (within one step of the accumulator).
  EXPECT_NEAR(double(steps), 1.0 / double(world.settings().dt), 1.01);
  EXPECT_EQ(world.stepCount(), steps);
  for (BodyId b : world.rigidBodies().bodies()) {
    const Transform t = world.transform(b);
    ASSERT_TRUE(t.p.allFinite() && t.q.coeffs().allFinite()) << world.rigidBodies().name(b);
    ASSERT_TRUE(world.linearVelocity(b).allFinite() && world.angularVelocity(b).allFinite());
  }
  for (ParticleSystemId id : world.particleSystems()) {
    const ParticlePool& pool = world.particleSystem(id).pool();
    const auto x = pool.positions();
    for (std::size_t i = 0; i < 3 * pool.size(); ++i) ASSERT_TRUE(std::isfinite(x[i]));
  }
  for (const Transform& t : playback.drawPoses()) ASSERT_TRUE(t.p.allFinite());
}

TEST(Samples, EverySceneFileIsListed) {
  std::set<std::string> files;
  for (const fs::directory_entry& e : fs::directory_iterator(scenesDir()))
    if (e.path().extension() == ".json") files.insert(fs::canonical(e.path()).string());
  ASSERT_GE(files.size(), 5u);
  std::set<std::string> listed;
  for (const Sample& s : allSamples(scenesDir()))
    if (!s.file.empty()) listed.insert(fs::canonical(s.file).string());
  EXPECT_EQ(listed, files);
}

TEST(Samples, ParticleScenesAreGroupedApart) {
  for (const Sample& s : sceneFileSamples(scenesDir())) {
    const io::Scene scene = s.build();
    EXPECT_EQ(s.group, scene.particleSystems.empty() ? "Scenes" : "Particles") << s.name;
  }
}

TEST(Samples, BuiltinsAreGroupedAndUseTheSharedBuilders) {
  const std::vector<Sample> builtins = builtinSamples();
  const std::vector<std::string> groups = sampleGroups(builtins);
  EXPECT_EQ(groups, (std::vector<std::string>{"Stacking", "Collision", "Contacts"}));
  std::set<std::string> names;
  for (const Sample& s : builtins) {
    EXPECT_TRUE(s.file.empty());
    EXPECT_TRUE(names.insert(s.group + "/" + s.name).second) << "duplicate " << s.name;
  }
  // The pyramid sample is the builder's pyramid on a ground plane, not a copy of it.
  const auto it = std::find_if(builtins.begin(), builtins.end(),
                               [](const Sample& s) { return s.name == "Pyramid (10)"; });
  ASSERT_NE(it, builtins.end());
  const io::Scene scene = it->build();
  const std::vector<BodyDesc> expected = pyramid({.base = 10});
  ASSERT_EQ(scene.bodies.size(), expected.size() + 1);
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_TRUE(scene.bodies[i + 1].settings.position.isApprox(expected[i].settings.position));
}

TEST(Samples, SceneFilesRunSixtyFrames) {
  const std::vector<Sample> samples = sceneFileSamples(scenesDir());
  ASSERT_FALSE(samples.empty());
  for (const Sample& s : samples) runSixtyFrames(s);
}

TEST(Samples, BuiltinsRunSixtyFrames) {
  for (const Sample& s : builtinSamples()) runSixtyFrames(s);
}

TEST(Samples, FindByFileOrName) {
  const std::vector<Sample> samples = allSamples(scenesDir());
  const std::optional<std::size_t> byFile =
      findSample(samples, (scenesDir() / "pyramid.json").string());
  ASSERT_TRUE(byFile);
  EXPECT_EQ(samples[*byFile].name, "pyramid");
  const std::optional<std::size_t> byName = findSample(samples, "Tower (12)");
  ASSERT_TRUE(byName);
  EXPECT_EQ(samples[*byName].group, "Stacking");
  EXPECT_FALSE(findSample(samples, "no such sample"));
}

TEST(Samples, ScenesFolderIsFoundNearTheExecutableOrTheSources) {
  const fs::path tmp = fs::temp_directory_path() / "inertia_samples_test";
  fs::remove_all(tmp);
  fs::create_directories(tmp / "scenes");
  fs::create_directories(tmp / "build" / "x" / "apps" / "inertia");
  const fs::path exe = tmp / "build" / "x" / "apps" / "inertia" / "inertia";
  EXPECT_EQ(findScenesDir(std::nullopt, exe, ""), tmp / "scenes");
  EXPECT_EQ(findScenesDir(std::nullopt, "", tmp), tmp / "scenes");
  EXPECT_EQ(findScenesDir(tmp / "build", exe, ""), tmp / "build");  // an explicit folder wins
  EXPECT_FALSE(findScenesDir(tmp / "missing", exe, tmp));
  // A broken file is still listed (its error shows when chosen) and fails to build.
  std::ofstream(tmp / "scenes" / "broken.json") << "{ not json";
  const std::vector<Sample> listed = sceneFileSamples(tmp / "scenes");
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_EQ(listed[0].name, "broken");
  EXPECT_THROW(listed[0].build(), io::SceneError);
  EXPECT_TRUE(sceneFileSamples(tmp / "missing").empty());
  fs::remove_all(tmp);
}

}  // namespace
}  // namespace inertia::viewer
