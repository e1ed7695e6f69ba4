// The shapes' "filter" key: read into each shape's CollisionFilter, and refused with the JSON
// pointer of the bad value.
#include <gtest/gtest.h>

#include <string>

#include "inertia/io/scene.h"

using namespace inertia;

namespace {

// The pointer of the SceneError that parsing `text` throws; empty when it parses.
std::string filterErrorPointer(const std::string& text) {
  try {
    (void)io::parseScene(text, "filter.json");
  } catch (const io::SceneError& e) {
    return e.pointer();
  }
  return {};
}

}  // namespace

TEST(FilterKey, ReadsCategoryMaskAndGroup) {
  const io::Scene s = io::parseScene(
      R"({"bodies": [{"shapes": [{"type": "sphere", "radius": 1,
                                  "filter": {"category": 2, "mask": 4294967293, "group": -7}},
                                 {"type": "sphere", "radius": 1}]}]})",
      "filter.json");
  ASSERT_EQ(s.bodies.size(), 1u);
  ASSERT_EQ(s.bodies[0].shapes.size(), 2u);
  EXPECT_EQ(s.bodies[0].shapes[0].filter,
            (CollisionFilter{.category = 2, .mask = ~2u, .group = -7}));
  EXPECT_EQ(s.bodies[0].shapes[1].filter, CollisionFilter{});
}

TEST(FilterKey, BadValuesNameTheirPointer) {
  const std::string head = R"({"bodies": [{"shapes": [{"type": "sphere", "radius": 1, "filter": )";
  const std::string tail = "}]}]}";
  EXPECT_EQ(filterErrorPointer(head + R"({"category": -1})" + tail),
            "/bodies/0/shapes/0/filter/category");
  EXPECT_EQ(filterErrorPointer(head + R"({"mask": 4294967296})" + tail),
            "/bodies/0/shapes/0/filter/mask");
  EXPECT_EQ(filterErrorPointer(head + R"({"group": 0.5})" + tail),
            "/bodies/0/shapes/0/filter/group");
  EXPECT_EQ(filterErrorPointer(head + R"({"layer": 1})" + tail), "/bodies/0/shapes/0/filter/layer");
  EXPECT_EQ(filterErrorPointer(head + "3" + tail), "/bodies/0/shapes/0/filter");
}
