// Scene files (JSON, DESIGN.md section 4): loading with errors that name the file, the JSON
// pointer and what is wrong.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "inertia/core/types.h"
#include "inertia/deformable/deformable.h"
#include "inertia/dynamics/joint.h"
#include "inertia/particles/particle_system.h"
#include "inertia/world/builders.h"
#include "inertia/world/world.h"

namespace inertia::io {

/// A problem with a scene file. what() reads "FILE: POINTER: REASON" (or "FILE:LINE:COL: REASON"
/// for a syntax error), so that a user can find the offending value.
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, std::string pointer, std::string reason);
  const std::string& file() const { return file_; }
  /// The JSON pointer of the offending value (RFC 6901), e.g. "/world/dt"; empty for syntax errors.
  const std::string& pointer() const { return pointer_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_, pointer_, reason_;
};

/// Where the viewer and renderer look from.
struct Camera {
  Vec3 position = Vec3(0, 5, 15);  ///< Eye (m).
  Vec3 target = Vec3(0, 0, 0);     ///< Point looked at (m).
  Real fov = 45;                   ///< Vertical field of view (degrees).
};

/// A particle system as described in a scene.
struct ParticleSystemDesc {
  ParticleSystemSettings settings;
  std::vector<EmitterSettings> emitters;
  std::vector<ForceField> fields;
  std::vector<Obstacle> obstacles;
};

/// A deformable as described in a scene: its settings, the model its generator built (pins
/// included) and its force fields.
struct DeformableDesc {
  DeformableSettings settings;
  MassSpringModel model;
  std::vector<ForceField> fields;
  /// Attachments; their `body` is filled in by instantiate() from bodyNames (same order).
  std::vector<Attachment> attachments;
  std::vector<std::string> attachmentBodies;
};

/// A joint as described in a scene: its settings, with the bodies given as indices into
/// Scene::bodies (the settings' bodyA and bodyB are filled in by instantiate()).
struct JointDesc {
  AnyJointSettings settings;
  std::optional<std::size_t> bodyA;  ///< Index into Scene::bodies; none: the world.
  std::size_t bodyB = 0;             ///< Index into Scene::bodies.
  /// Its JSON pointer, for errors: "/joints/2", or the generator's ("/bodies/3") for a joint
  /// that a generator made.
  std::string pointer;
};

/// An articulation as described in a scene: the World's settings for it (model, shapes, base
/// and initial state) and its JSON pointer, for errors that only createArticulation finds.
struct ArticulationDesc {
  WorldArticulationSettings settings;
  std::string pointer;
};

/// A scene as read from a file: plain data, checked, not yet simulated.
struct Scene {
  std::filesystem::path file;  ///< Where it was read from (for relative paths and messages).
  WorldSettings world;
  std::optional<Camera> camera;
  std::vector<BodyDesc> bodies;  ///< Generators already expanded, in file order.
  /// The generators' joints (a ragdoll's), in the order of "bodies", then the "joints" section
  /// in file order: the order instantiate() creates them.
  std::vector<JointDesc> joints;
  std::vector<ParticleSystemDesc> particleSystems;
  std::vector<DeformableDesc> deformables;
  std::vector<ArticulationDesc> articulations;
};

/// Appends an assembly's bodies and joints (inertia/world/builders.h) to `scene`, its joints'
/// body indices shifted to the scene's; `pointer` is the joints' JSON pointer for errors (the
/// generator's in a file). How generators and the viewer's samples put jointed builders into
/// scenes.
void append(Scene& scene, const Assembly& assembly, const std::string& pointer = {});

/// Reads and checks a scene file. Throws SceneError on a missing file, bad JSON, an unknown
/// key, a value of the wrong type or out of range.
Scene loadScene(const std::filesystem::path& file);

/// Parses scene text; `name` is used in error messages (and relative paths resolve against
/// its directory).
Scene parseScene(const std::string& text, const std::filesystem::path& name);

/// Builds a world from a scene. Throws InvalidArgument as World::createBody does, and
/// SceneError naming the joint's JSON pointer when World::createJoint refuses a joint.
std::unique_ptr<World> instantiate(const Scene& scene);

}  // namespace inertia::io
