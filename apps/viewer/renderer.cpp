#include "renderer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "offscreen.h"
#include "shape_mesh.h"

namespace inertia::viewer {

namespace {

// Lambert diffuse plus a hemisphere ambient and a Blinn-Phong highlight; planes get an
// anti-aliased grid (line width from the screen-space derivative) and distance fog.
const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
uniform mat4 uViewProj;
uniform mat4 uModel;
uniform mat3 uNormalMatrix;
out vec3 vWorld;
out vec3 vNormal;
void main() {
  vec4 world = uModel * vec4(aPosition, 1.0);
  vWorld = world.xyz;
  vNormal = uNormalMatrix * aNormal;
  gl_Position = uViewProj * world;
}
)";

const char* kMeshFragment = R"(#version 330 core
in vec3 vWorld;
in vec3 vNormal;
uniform vec3 uColor;
uniform vec3 uToLight;
uniform vec3 uEye;
uniform vec3 uFogColor;
uniform vec2 uFogRange;
uniform int uGrid;
uniform vec3 uGridU;
uniform vec3 uGridV;
out vec4 fragColor;
void main() {
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 base = uColor;
  if (uGrid == 1) {
    vec2 g = vec2(dot(vWorld, uGridU), dot(vWorld, uGridV));
    vec2 w = max(fwidth(g), vec2(1e-4));
    vec2 d = abs(fract(g - 0.5) - 0.5) / w;
    float line = 1.0 - min(min(d.x, d.y), 1.0);
    float fade = clamp(1.0 - 3.0 * max(w.x, w.y), 0.0, 1.0);
    base = mix(base, base * 0.6, line * fade);
  }
  float diffuse = max(dot(n, uToLight), 0.0);
  vec3 ambient = mix(vec3(0.20, 0.19, 0.18), vec3(0.36, 0.39, 0.44), 0.5 + 0.5 * n.y);
  vec3 h = normalize(uToLight + normalize(uEye - vWorld));
  float specular = diffuse > 0.0 ? 0.2 * pow(max(dot(n, h), 0.0), 48.0) : 0.0;
  vec3 color = base * (ambient + 0.75 * diffuse) + vec3(specular);
  float f = clamp((length(uEye - vWorld) - uFogRange.x) / (uFogRange.y - uFogRange.x), 0.0, 1.0);
  fragColor = vec4(mix(color, uFogColor, f), 1.0);
}
)";

// Point sprites sized by the particle's radius in perspective, shaded as little spheres.
const char* kPointVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aColor;
layout(location = 2) in float aRadius;
uniform mat4 uView;
uniform mat4 uProj;
uniform float uPointScale;
out vec3 vColor;
void main() {
  vec4 view = uView * vec4(aPosition, 1.0);
  gl_Position = uProj * view;
  gl_PointSize = max(2.0, 2.0 * aRadius * uPointScale / max(-view.z, 1e-3));
  vColor = aColor;
}
)";

const char* kPointFragment = R"(#version 330 core
in vec3 vColor;
uniform vec3 uToLightView;
out vec4 fragColor;
void main() {
  vec2 p = 2.0 * gl_PointCoord - 1.0;
  float r2 = dot(p, p);
  if (r2 > 1.0) discard;
  vec3 n = vec3(p.x, -p.y, sqrt(1.0 - r2));
  fragColor = vec4(vColor * (0.5 + 0.5 * max(dot(n, uToLightView), 0.0)), 1.0);
}
)";

GLuint compile(GLenum type, const char* source) {
  GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw GlError(std::string("shader compilation failed: ") + log);
  }
  return shader;
}

GLuint link(const char* vertex, const char* fragment) {
  GLuint vs = compile(GL_VERTEX_SHADER, vertex);
  GLuint fs = compile(GL_FRAGMENT_SHADER, fragment);
  GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    glDeleteProgram(program);
    throw GlError(std::string("shader link failed: ") + log);
  }
  return program;
}

GLint at(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

void setVec3(GLuint program, const char* name, const Eigen::Vector3f& v) {
  glUniform3f(at(program, name), v.x(), v.y(), v.z());
}

std::uint64_t key(ShapeId id) { return (std::uint64_t(id.index) << 32) | id.generation; }
// Obstacles of particle systems: the top bit apart from body shapes.
std::uint64_t key(ParticleSystemId id, std::size_t obstacle) {
  return (std::uint64_t(1) << 63) | (std::uint64_t(id.index & 0x7fffff) << 40) |
         (std::uint64_t(id.generation & 0xff) << 32) | std::uint64_t(obstacle & 0xffffffff);
}

Eigen::Vector3f hsv(float h, float s, float v) {
  const float r = std::clamp(std::abs(h * 6 - 3) - 1, 0.0f, 1.0f);
  const float g = std::clamp(2 - std::abs(h * 6 - 2), 0.0f, 1.0f);
  const float b = std::clamp(2 - std::abs(h * 6 - 4), 0.0f, 1.0f);
  return v * ((1 - s) * Eigen::Vector3f::Ones() + s * Eigen::Vector3f(r, g, b));
}

}  // namespace

GLuint linkProgram(const char* vertexSource, const char* fragmentSource) {
  return link(vertexSource, fragmentSource);
}

Eigen::Vector3f defaultBodyColor(std::size_t bodyIndex, BodyType type) {
  if (type == BodyType::Static) return Eigen::Vector3f(0.72f, 0.72f, 0.70f);
  const double golden = 0.618033988749895;
  const float hue = float(std::fmod(0.08 + golden * double(bodyIndex), 1.0));
  return hsv(hue, 0.55f, 0.9f);
}

Renderer::Renderer() {
  meshProgram_ = link(kMeshVertex, kMeshFragment);
  pointProgram_ = link(kPointVertex, kPointFragment);
  glGenVertexArrays(1, &pointVao_);
  glGenBuffers(1, &pointVbo_);
  glBindVertexArray(pointVao_);
  glBindBuffer(GL_ARRAY_BUFFER, pointVbo_);
  const GLsizei stride = 7 * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<void*>(6 * sizeof(float)));
  glBindVertexArray(0);
}

Renderer::~Renderer() {
  for (auto& [k, m] : meshes_) {
    glDeleteVertexArrays(1, &m.vao);
    glDeleteBuffers(1, &m.vbo);
    glDeleteBuffers(1, &m.ibo);
  }
  glDeleteVertexArrays(1, &pointVao_);
  glDeleteBuffers(1, &pointVbo_);
  glDeleteVertexArrays(1, &deformable_.vao);
  glDeleteBuffers(1, &deformable_.vbo);
  glDeleteBuffers(1, &deformable_.ibo);
  glDeleteProgram(meshProgram_);
  glDeleteProgram(pointProgram_);
}

Renderer::GpuMesh& Renderer::meshFor(std::uint64_t key, const Shape& shape) {
  auto [it, inserted] = meshes_.try_emplace(key);
  GpuMesh& g = it->second;
  g.used = true;
  if (!inserted) return g;
  const MeshData m = tessellate(shape, {.segments = style_.segments, .planeHalfSize = 1000});
  std::vector<float> interleaved;
  interleaved.reserve(6 * m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    interleaved.insert(interleaved.end(), m.positions[i].data(), m.positions[i].data() + 3);
    interleaved.insert(interleaved.end(), m.normals[i].data(), m.normals[i].data() + 3);
  }
  glGenVertexArrays(1, &g.vao);
  glGenBuffers(1, &g.vbo);
  glGenBuffers(1, &g.ibo);
  glBindVertexArray(g.vao);
  glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(interleaved.size() * sizeof(float)), interleaved.data(),
               GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(m.indices.size() * sizeof(std::uint32_t)),
               m.indices.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<void*>(3 * sizeof(float)));
  glBindVertexArray(0);
  g.count = GLsizei(m.indices.size());
  return g;
}

// Each deformable's mesh (deformableMesh: world coordinates) streamed into one set of buffers
// and drawn with the mesh program, in a colour per deformable (warm hues, apart from bodies').
void Renderer::drawDeformables(const World& world) {
  const std::vector<DeformableId> ids = world.deformables();
  if (ids.empty()) return;
  if (deformable_.vao == 0) {
    glGenVertexArrays(1, &deformable_.vao);
    glGenBuffers(1, &deformable_.vbo);
    glGenBuffers(1, &deformable_.ibo);
    glBindVertexArray(deformable_.vao);
    glBindBuffer(GL_ARRAY_BUFFER, deformable_.vbo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, deformable_.ibo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                          reinterpret_cast<void*>(3 * sizeof(float)));
  }
  const Eigen::Matrix4f identity = Eigen::Matrix4f::Identity();
  const Eigen::Matrix3f normalMatrix = Eigen::Matrix3f::Identity();
  glUniform1i(at(meshProgram_, "uGrid"), 0);
  glUniformMatrix4fv(at(meshProgram_, "uModel"), 1, GL_FALSE, identity.data());
  glUniformMatrix3fv(at(meshProgram_, "uNormalMatrix"), 1, GL_FALSE, normalMatrix.data());
  glBindVertexArray(deformable_.vao);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const Deformable& d = world.deformable(ids[k]);
    const MeshData m =
        deformableMesh(d, 6, std::max(d.settings().thickness, Real(0.002)));
    deformableData_.clear();
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      deformableData_.insert(deformableData_.end(), m.positions[i].data(),
                             m.positions[i].data() + 3);
      deformableData_.insert(deformableData_.end(), m.normals[i].data(), m.normals[i].data() + 3);
    }
    glBindBuffer(GL_ARRAY_BUFFER, deformable_.vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(deformableData_.size() * sizeof(float)),
                 deformableData_.data(), GL_STREAM_DRAW);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(m.indices.size() * sizeof(std::uint32_t)),
                 m.indices.data(), GL_STREAM_DRAW);
    const double golden = 0.618033988749895;
    setVec3(meshProgram_, "uColor",
            hsv(float(std::fmod(0.95 + 0.3 * golden * double(k), 1.0)), 0.6f, 0.85f));
    glDrawElements(GL_TRIANGLES, GLsizei(m.indices.size()), GL_UNSIGNED_INT, nullptr);
  }
}

void Renderer::drawShape(std::uint64_t key, const Shape& shape, const Transform& pose,
                         const Eigen::Vector3f& color) {
  const Eigen::Affine3f model = Eigen::Translation3f(pose.p.cast<float>()) * pose.q.cast<float>();
  const Eigen::Matrix3f normalMatrix = pose.q.cast<float>().toRotationMatrix();
  const Plane* plane = shape.getIf<Plane>();
  if (plane) {
    Vec3 u, v;
    planeBasis(pose.rotate(plane->normal), u, v);
    setVec3(meshProgram_, "uGridU", u.cast<float>());
    setVec3(meshProgram_, "uGridV", v.cast<float>());
  }
  glUniform1i(at(meshProgram_, "uGrid"), plane ? 1 : 0);
  glUniformMatrix4fv(at(meshProgram_, "uModel"), 1, GL_FALSE, model.matrix().data());
  glUniformMatrix3fv(at(meshProgram_, "uNormalMatrix"), 1, GL_FALSE, normalMatrix.data());
  setVec3(meshProgram_, "uColor", color);
  const GpuMesh& g = meshFor(key, shape);
  glBindVertexArray(g.vao);
  glDrawElements(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr);
}

void Renderer::draw(const World& world, const CameraView& camera, int width, int height,
                    std::span<const Transform> bodyPoses) {
  const Eigen::Vector3f& bg = style_.background;
  glClearColor(bg.x(), bg.y(), bg.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);  // meshes and height fields may be open: shade both sides

  const float aspect = float(width) / float(std::max(1, height));
  const Eigen::Matrix4f view = viewMatrix(camera);
  const Eigen::Matrix4f proj = projectionMatrix(camera, aspect);
  const Eigen::Matrix4f viewProj = proj * view;
  const Eigen::Vector3f toLight = -style_.lightDirection.normalized();
  const float distance = (camera.target - camera.position).norm();

  glUseProgram(meshProgram_);
  glUniformMatrix4fv(at(meshProgram_, "uViewProj"), 1, GL_FALSE, viewProj.data());
  setVec3(meshProgram_, "uToLight", toLight);
  setVec3(meshProgram_, "uEye", camera.position);
  setVec3(meshProgram_, "uFogColor", bg);
  glUniform2f(at(meshProgram_, "uFogRange"), 3 * distance,
              std::clamp(12 * distance, 60.0f, 900.0f));

  for (auto& [k, m] : meshes_) m.used = false;
  const RigidBodySystem& rb = world.rigidBodies();
  const std::vector<BodyId> bodies = rb.bodies();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::vector<ShapeId> shapes = rb.shapes(bodies[i]);
    const BodyType type = rb.type(bodies[i]);
    const bool asleep = style_.sleepingColor && type == BodyType::Dynamic && !rb.isAwake(bodies[i]);
    // A given pose moves the body's shapes rigidly: shape = pose * (body^-1 * shape now).
    const bool posed = i < bodyPoses.size();
    const Transform toPose = posed ? bodyPoses[i] * rb.transform(bodies[i]).inverse() : Transform{};
    for (std::size_t j = 0; j < shapes.size(); ++j) {
      Eigen::Vector3f color = defaultBodyColor(i, type);
      if (i < colors_.size() && j < colors_[i].size() && colors_[i][j])
        color = colors_[i][j]->cast<float>();
      if (asleep) color = *style_.sleepingColor;
      const Transform shapePose = rb.shapeTransform(shapes[j]);
      drawShape(key(shapes[j]), rb.collider(shapes[j]).shape(),
                posed ? toPose * shapePose : shapePose, color);
    }
  }
  if (style_.particles) {
    for (ParticleSystemId id : world.particleSystems()) {
      const auto obstacles = world.particleSystem(id).obstacles();
      for (std::size_t k = 0; k < obstacles.size(); ++k) {
        const Shape& shape = obstacles[k].collider.shape();
        const Eigen::Vector3f color = shape.type() == ShapeType::Plane
                                          ? defaultBodyColor(0, BodyType::Static)
                                          : Eigen::Vector3f(0.55f, 0.56f, 0.6f);
        drawShape(key(id, k), shape, obstacles[k].pose, color);
      }
    }
  }
  drawDeformables(world);
  glBindVertexArray(0);
  // Shapes that disappeared (destroyed bodies) free their buffers.
  for (auto it = meshes_.begin(); it != meshes_.end();) {
    if (it->second.used) {
      ++it;
      continue;
    }
    glDeleteVertexArrays(1, &it->second.vao);
    glDeleteBuffers(1, &it->second.vbo);
    glDeleteBuffers(1, &it->second.ibo);
    it = meshes_.erase(it);
  }

  if (style_.particles) {
    const float pointScale =
        float(height) / (2 * std::tan(camera.fovY * std::numbers::pi_v<float> / 360.0f));
    drawParticles(world, view, proj, pointScale);
  }
  glUseProgram(0);
}

void Renderer::drawParticles(const World& world, const Eigen::Matrix4f& view,
                             const Eigen::Matrix4f& proj, float pointScale) {
  pointData_.clear();
  for (ParticleSystemId id : world.particleSystems()) {
    const ParticlePool& pool = world.particleSystem(id).pool();
    const auto x = pool.positions();
    const auto c = pool.colors();
    const auto r = pool.radii();
    const auto age = pool.ages();
    const auto life = pool.lifetimes();
    for (std::size_t i = 0; i < pool.size(); ++i) {
      float shade = 1;
      if (style_.colorOverLife && std::isfinite(life[i]) && life[i] > 0) {
        const float t = std::clamp(float(age[i] / life[i]), 0.0f, 1.0f);
        shade = 1 - 0.55f * t * t;
      }
      pointData_.insert(
          pointData_.end(),
          {float(x[3 * i]), float(x[3 * i + 1]), float(x[3 * i + 2]), shade * float(c[3 * i]),
           shade * float(c[3 * i + 1]), shade * float(c[3 * i + 2]), float(r[i])});
    }
  }
  if (pointData_.empty()) return;
  glEnable(GL_PROGRAM_POINT_SIZE);
  glUseProgram(pointProgram_);
  glUniformMatrix4fv(at(pointProgram_, "uView"), 1, GL_FALSE, view.data());
  glUniformMatrix4fv(at(pointProgram_, "uProj"), 1, GL_FALSE, proj.data());
  glUniform1f(at(pointProgram_, "uPointScale"), pointScale);
  const Eigen::Vector3f toLightView =
      (view.block<3, 3>(0, 0) * -style_.lightDirection.normalized()).normalized();
  setVec3(pointProgram_, "uToLightView", toLightView);
  glBindVertexArray(pointVao_);
  glBindBuffer(GL_ARRAY_BUFFER, pointVbo_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(pointData_.size() * sizeof(float)), pointData_.data(),
               GL_STREAM_DRAW);
  glDrawArrays(GL_POINTS, 0, GLsizei(pointData_.size() / 7));
  glBindVertexArray(0);
}

}  // namespace inertia::viewer
