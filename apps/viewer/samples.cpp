// The sample browser's list: scene files peeked at for their group, built-in samples made
// by the shared builders (samples.h).
#include "samples.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <system_error>

#include "inertia/world/builders.h"

namespace inertia::viewer {

namespace {

namespace fs = std::filesystem;

// Bodies are filled field by field: nested designated initialisers of BodyDesc trip GCC 12's
// false -Wmaybe-uninitialized on BodySettings::name.
BodyDesc body(BodyType type, const Vec3& position, const Quat& orientation, const Shape& shape,
              const Material& material = {}) {
  BodyDesc b;
  b.settings.type = type;
  b.settings.position = position;
  b.settings.orientation = orientation;
  ShapeDesc& s = b.shapes.emplace_back();
  s.shape = shape;
  s.material = material;
  return b;
}

BodyDesc ground() {
  BodyDesc b = body(BodyType::Static, Vec3::Zero(), Quat::Identity(), Plane{Vec3::UnitY(), 0});
  b.settings.name = "ground";
  return b;
}

io::Scene sceneOf(std::vector<BodyDesc> bodies, const Vec3& eye, const Vec3& target) {
  io::Scene scene;
  scene.file = "builtin";
  scene.camera = io::Camera{.position = eye, .target = target, .fov = 45};
  scene.bodies.push_back(ground());
  for (BodyDesc& b : bodies) scene.bodies.push_back(std::move(b));
  return scene;
}

// Spheres dropped side by side, restitution 0 to 1 from left to right.
io::Scene restitutionRow() {
  std::vector<BodyDesc> bodies;
  for (int i = 0; i <= 5; ++i) {
    Material m;
    m.restitution = Real(i) / 5;
    bodies.push_back(body(BodyType::Dynamic, Vec3(Real(1.2) * Real(i - 3) + Real(0.6), 4, 0),
                          Quat::Identity(), Sphere{Real(0.4)}, m));
  }
  return sceneOf(std::move(bodies), Vec3(0, 3, 11), Vec3(0, 2, 0));
}

// Boxes on a 25-degree ramp, friction 0.1 to 0.7 (tan 25 deg = 0.47: the last two hold).
io::Scene frictionRamp() {
  const Real angle = Real(25) * std::numbers::pi_v<Real> / 180;
  const Quat tilt(Eigen::AngleAxis<Real>(angle, Vec3::UnitZ()));
  std::vector<BodyDesc> bodies;
  bodies.push_back(body(BodyType::Static, Vec3(0, 2, 0), tilt, Box{Vec3(6, Real(0.2), 4)}));
  bodies.back().settings.name = "ramp";
  for (int i = 0; i < 4; ++i) {
    const Vec3 local(3, Real(0.2) + Real(0.3), Real(-3) + Real(2) * Real(i));
    Material m;
    m.friction = Real(0.1) + Real(0.2) * Real(i);
    bodies.push_back(body(BodyType::Dynamic, Vec3(0, 2, 0) + tilt * local, tilt,
                          Box{Vec3::Constant(Real(0.3))}, m));
  }
  return sceneOf(std::move(bodies), Vec3(-7, 8, 13), Vec3(0, 2, 0));
}

}  // namespace

std::vector<Sample> builtinSamples() {
  std::vector<Sample> s;
  s.push_back({"Stacking", "Pyramid (10)",
               [] { return sceneOf(pyramid({.base = 10}), Vec3(0, 5, 20), Vec3(0, 4, 0)); }});
  s.push_back({"Stacking", "Tower (12)",
               [] { return sceneOf(tower({.height = 12}), Vec3(0, 6, 18), Vec3(0, 5, 0)); }});
  s.push_back({"Stacking", "Brick wall", [] {
                 return sceneOf(wall({.rows = 8, .columns = 10}), Vec3(0, 3, 14), Vec3(0, 2, 0));
               }});
  s.push_back({"Collision", "Box rain",
               [] { return sceneOf(rain({.count = 150}), Vec3(0, 10, 26), Vec3(0, 4, 0)); }});
  s.push_back({"Collision", "Capsule rain", [] {
                 return sceneOf(rain({.count = 120, .shape = Capsule{Real(0.3), Real(0.4)}}),
                                Vec3(0, 10, 26), Vec3(0, 4, 0));
               }});
  s.push_back({"Collision", "Sphere lattice", [] {
                 return sceneOf(grid({.counts = {6, 6, 6}, .origin = Vec3(-2.75, 1, -2.75)}),
                                Vec3(0, 8, 20), Vec3(0, 3, 0));
               }});
  s.push_back({"Contacts", "Restitution row", restitutionRow});
  s.push_back({"Contacts", "Friction ramp", frictionRamp});
  return s;
}

std::vector<Sample> sceneFileSamples(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.is_regular_file(ec) && e.path().extension() == ".json") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<Sample> samples;
  for (const fs::path& file : files) {
    // A peek, not a load: an unreadable or broken file still appears and reports its error
    // when chosen.
    std::string group = "Scenes";
    std::ifstream in(file);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_object() && j.contains("particle_systems") && j["particle_systems"].is_array() &&
        !j["particle_systems"].empty())
      group = "Particles";
    samples.push_back({group, file.stem().string(), [file] { return io::loadScene(file); }, file});
  }
  return samples;
}

std::vector<Sample> allSamples(const std::optional<fs::path>& scenesDir) {
  std::vector<Sample> samples;
  if (scenesDir) samples = sceneFileSamples(*scenesDir);
  for (Sample& s : builtinSamples()) samples.push_back(std::move(s));
  return samples;
}

std::optional<std::size_t> findSample(const std::vector<Sample>& samples,
                                      const std::string& nameOrFile) {
  std::error_code ec;
  const fs::path wanted = fs::weakly_canonical(nameOrFile, ec);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].file.empty() && !ec) {
      std::error_code ec2;
      if (fs::weakly_canonical(samples[i].file, ec2) == wanted && !ec2) return i;
    }
  }
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].name == nameOrFile) return i;
  return std::nullopt;
}

std::optional<fs::path> findScenesDir(const std::optional<fs::path>& explicitDir,
                                      const fs::path& executable, const fs::path& sourceDir) {
  std::error_code ec;
  if (explicitDir) {
    if (fs::is_directory(*explicitDir, ec)) return *explicitDir;
    return std::nullopt;
  }
  if (!executable.empty()) {
    fs::path dir = executable.parent_path();
    for (int up = 0; up <= 4 && !dir.empty(); ++up, dir = dir.parent_path()) {
      if (fs::is_directory(dir / "scenes", ec)) return dir / "scenes";
      if (dir == dir.root_path()) break;
    }
  }
  if (!sourceDir.empty() && fs::is_directory(sourceDir / "scenes", ec)) return sourceDir / "scenes";
  return std::nullopt;
}

std::vector<std::string> sampleGroups(const std::vector<Sample>& samples) {
  std::vector<std::string> groups;
  for (const Sample& s : samples)
    if (std::find(groups.begin(), groups.end(), s.group) == groups.end()) groups.push_back(s.group);
  return groups;
}

}  // namespace inertia::viewer
