#include "inertia/io/scene.h"

#include <fstream>
#include <map>
#include <sstream>
#include <variant>

#include "articulations_section.h"
#include "bodies_section.h"
#include "deformables_section.h"
#include "inertia/core/error.h"
#include "joints_section.h"
#include "json_reader.h"
#include "particles_section.h"

namespace inertia::io {

using detail::Json;
using detail::Node;

SceneError::SceneError(std::string file, std::string pointer, std::string reason)
    : std::runtime_error(file + ": " + (pointer.empty() ? std::string() : pointer + ": ") + reason),
      file_(std::move(file)),
      pointer_(std::move(pointer)),
      reason_(std::move(reason)) {}

namespace {

std::string integratorNames() {
  std::string list;
  for (std::string_view name : ode::kMethodNames) list += (list.empty() ? "" : ", ") + std::string(name);
  return list;
}

void readSolver(const Node& n, SolverSettings& s) {
  n.requireObject({"type", "iterations", "relax_iterations", "joint_hertz", "joint_damping_ratio"});
  if (n.has("type")) {
    Node t = n.at("type");
    if (!solverFromName(t.string(), s.type))
      t.fail("unknown solver \"" + t.string() + "\"; expected one of " + std::string(solverNames()));
  }
  if (n.has("iterations")) s.iterations = int(n.at("iterations").integer(1, 1000));
  if (n.has("relax_iterations"))
    s.relaxIterations = int(n.at("relax_iterations").integer(0, 1000));
  if (n.has("joint_hertz"))
    s.jointHertz = Real(n.at("joint_hertz").number(0, 1e6, /*openLo=*/true));
  if (n.has("joint_damping_ratio"))
    s.jointDampingRatio = Real(n.at("joint_damping_ratio").number(0, 1e6));
}

void readWorld(const Node& n, WorldSettings& w) {
  n.requireObject({"gravity", "dt", "substeps", "solver", "integrator", "threads", "sleeping"});
  if (n.has("gravity")) w.gravity = n.at("gravity").vec3();
  if (n.has("dt")) w.dt = Real(n.at("dt").number(0, 1, /*openLo=*/true));
  if (n.has("substeps")) w.substeps = int(n.at("substeps").integer(1, 64));
  if (n.has("solver")) readSolver(n.at("solver"), w.solver);
  if (n.has("integrator")) {
    Node i = n.at("integrator");
    auto method = ode::methodFromName(i.string());
    if (!method) i.fail("unknown integrator \"" + i.string() + "\"; expected one of " + integratorNames());
    w.integrator = *method;
  }
  if (n.has("threads")) w.threads = int(n.at("threads").integer(0, 1024));
  if (n.has("sleeping")) w.sleeping = n.at("sleeping").boolean();
}

Camera readCamera(const Node& n) {
  n.requireObject({"position", "target", "fov"});
  Camera c;
  if (n.has("position")) c.position = n.at("position").vec3();
  if (n.has("target")) c.target = n.at("target").vec3();
  if (n.has("fov")) c.fov = Real(n.at("fov").number(0, 180, /*openLo=*/true));
  if ((c.position - c.target).norm() <= Real(1e-6)) n.fail("camera position and target coincide");
  return c;
}

// Names identify bodies, joints and particle systems in recordings, and bodies in the
// references of joints and emitters: each must be unique among its kind. `seen` maps each name
// to the JSON pointer of what has it; a second one fails at `n` (its "name" when it has one).
class UniqueNames {
 public:
  UniqueNames(std::string kind, std::string plural)
      : kind_(std::move(kind)), plural_(std::move(plural)) {}
  void add(const Node& n, const std::string& name) {
    const auto [it, added] = seen_.emplace(name, n.pointer().to_string());
    if (added) return;
    const bool named = n.has("name");
    (named ? n.at("name") : n)
        .fail("duplicate " + kind_ + " name \"" + name + "\"" +
              (named ? "" : " (a name made for it, as it has no \"name\")") + ", already " +
              it->second + "'s: names tell " + plural_ + " apart in recordings and references");
  }

 private:
  std::string kind_, plural_;
  std::map<std::string, std::string> seen_;
};

std::string jointName(const AnyJointSettings& settings) {
  return std::visit([](const auto& s) { return s.name; }, settings);
}

}  // namespace

Scene parseScene(const std::string& text, const std::filesystem::path& name) {
  const std::string file = name.string();
  // Syntax errors have no JSON pointer: name the line and column instead, which editors understand.
  auto where = [&](std::size_t byte) {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
      if (text[i] == '\n') line++, column = 1;
      else column++;
    }
    return file + ":" + std::to_string(line) + ":" + std::to_string(column);
  };
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::parse_error& e) {
    std::string reason = e.what();
    if (auto pos = reason.find("syntax error"); pos != std::string::npos) reason = reason.substr(pos);
    throw SceneError(where(e.byte > 0 ? e.byte - 1 : 0), "", reason);
  } catch (const Json::out_of_range& e) {
    // A number too large for a double ("1e999"): the lexer names the token but not its place,
    // so find the token in the text.
    std::string reason = e.what();
    if (auto pos = reason.find("number overflow"); pos != std::string::npos) reason = reason.substr(pos);
    std::size_t byte = 0;
    if (auto q = reason.find('\''); q != std::string::npos) {
      std::string token = reason.substr(q + 1, reason.rfind('\'') - q - 1);
      if (auto at = text.find(token); at != std::string::npos) byte = at;
    }
    throw SceneError(where(byte), "", reason + " (not a finite number)");
  }

  Scene scene;
  scene.file = name;
  Node n(root, detail::Pointer(), file);
  n.requireObject({"world", "camera", "materials", "bodies", "joints", "particle_systems",
                   "deformables", "articulations"});
  if (n.has("world")) readWorld(n.at("world"), scene.world);
  if (n.has("camera")) scene.camera = readCamera(n.at("camera"));
  detail::MaterialTable materials;
  if (n.has("materials")) materials = detail::readMaterials(n.at("materials"));
  // A generator's bodies and joints are named by it: a clash names the generator.
  UniqueNames bodyNames("body", "bodies"), jointNames("joint", "joints"),
      systemNames("particle system", "particle systems");
  if (n.has("bodies")) {
    Node list = n.at("bodies");
    for (std::size_t i = 0; i < list.requireArray(); ++i) {
      const std::size_t bodies = scene.bodies.size(), joints = scene.joints.size();
      detail::readBodies(list.at(i), i, materials, scene);
      for (std::size_t b = bodies; b < scene.bodies.size(); ++b)
        bodyNames.add(list.at(i), scene.bodies[b].settings.name);
      for (std::size_t j = joints; j < scene.joints.size(); ++j)
        jointNames.add(list.at(i), jointName(scene.joints[j].settings));
    }
  }
  if (n.has("joints")) {
    Node list = n.at("joints");
    for (std::size_t i = 0; i < list.requireArray(); ++i) {
      scene.joints.push_back(detail::readJoint(list.at(i), i, scene.bodies));
      jointNames.add(list.at(i), jointName(scene.joints.back().settings));
    }
  }
  if (n.has("particle_systems")) {
    Node list = n.at("particle_systems");
    for (std::size_t i = 0; i < list.requireArray(); ++i) {
      scene.particleSystems.push_back(detail::readParticleSystem(list.at(i), i, scene.bodies));
      systemNames.add(list.at(i), scene.particleSystems.back().settings.name);
    }
  }
  if (n.has("deformables")) {
    Node list = n.at("deformables");
    for (std::size_t i = 0; i < list.requireArray(); ++i)
      scene.deformables.push_back(detail::readDeformable(list.at(i), i, scene.bodies));
  }
  if (n.has("articulations")) {
    // Their links are bodies named ARTICULATION/LINK: the names must not clash with the
    // bodies' either.
    UniqueNames articulationNames("articulation", "articulations");
    Node list = n.at("articulations");
    for (std::size_t i = 0; i < list.requireArray(); ++i) {
      scene.articulations.push_back(detail::readArticulation(list.at(i), i, materials));
      const ArticulationDesc& a = scene.articulations.back();
      articulationNames.add(list.at(i), a.settings.name);
      for (const auto& link : a.settings.model.links())
        bodyNames.add(list.at(i), a.settings.name + "/" + link.name);
    }
  }
  return scene;
}

void append(Scene& scene, const Assembly& assembly, const std::string& pointer) {
  const std::size_t n = assembly.bodies.size(), offset = scene.bodies.size();
  for (std::size_t i = 0; i < assembly.joints.size(); ++i) {
    const AssemblyJoint& j = assembly.joints[i];
    require(j.bodyA >= -1 && j.bodyA < int(n) && j.bodyB >= 0 && std::size_t(j.bodyB) < n,
            "Assembly::joints[" + std::to_string(i) + "]: body index out of range");
  }
  scene.bodies.insert(scene.bodies.end(), assembly.bodies.begin(), assembly.bodies.end());
  for (const AssemblyJoint& j : assembly.joints) {
    JointDesc& d = scene.joints.emplace_back();
    d.settings = j.settings;
    if (j.bodyA >= 0) d.bodyA = offset + std::size_t(j.bodyA);
    d.bodyB = offset + std::size_t(j.bodyB);
    d.pointer = pointer;
  }
}

Scene loadScene(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw SceneError(file.string(), "", "no such file");
  if (std::filesystem::is_directory(file, ec)) throw SceneError(file.string(), "", "is a directory, not a scene file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SceneError(file.string(), "", "cannot be opened for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return parseScene(text.str(), file);
}

std::unique_ptr<World> instantiate(const Scene& scene) {
  auto world = std::make_unique<World>(scene.world);
  std::vector<BodyId> bodies;
  bodies.reserve(scene.bodies.size());
  for (const BodyDesc& d : scene.bodies) bodies.push_back(addBody(*world, d));
  for (const JointDesc& d : scene.joints) {
    std::visit(
        [&](auto settings) {
          settings.bodyA = d.bodyA ? bodies.at(*d.bodyA) : BodyId{};
          settings.bodyB = bodies.at(d.bodyB);
          // The loader checks what it can see; the rest (what createJoint alone knows) is
          // reported at the joint.
          try {
            world->createJoint(settings);
          } catch (const InvalidArgument& e) {
            throw SceneError(scene.file.string(), d.pointer, e.what());
          }
        },
        d.settings);
  }
  // Emitters attached by name (checked unique when read) get the body's id.
  auto bodyNamed = [&](const std::string& name) {
    for (BodyId id : world->rigidBodies().bodies())
      if (world->rigidBodies().name(id) == name) return id;
    return BodyId{};
  };
  for (const ParticleSystemDesc& d : scene.particleSystems) {
    ParticleSystem& ps = world->particleSystem(world->createParticleSystem(d.settings));
    for (EmitterSettings e : d.emitters) {
      if (!e.attachToName.empty()) e.attachTo = bodyNamed(e.attachToName);
      ps.addEmitter(e);
    }
    for (const ForceField& f : d.fields) ps.addField(f);
    for (const Obstacle& o : d.obstacles) ps.addObstacle(o);
  }
  for (const ArticulationDesc& d : scene.articulations) {
    try {
      world->createArticulation(d.settings);
    } catch (const InvalidArgument& e) {
      throw SceneError(scene.file.string(), d.pointer, e.what());
    }
  }
  for (const DeformableDesc& d : scene.deformables) {
    Deformable& deformable = world->deformable(world->createDeformable(d.settings, d.model));
    for (const ForceField& f : d.fields) deformable.addField(f);
    for (std::size_t k = 0; k < d.attachments.size(); ++k) {
      Attachment a = d.attachments[k];
      a.body = bodyNamed(d.attachmentBodies[k]);
      deformable.addAttachment(a);
    }
  }
  return world;
}

}  // namespace inertia::io
