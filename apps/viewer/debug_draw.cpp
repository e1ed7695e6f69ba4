// Debug lines from a world's state and the GL program that draws them (debug_draw.h).
#include "debug_draw.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "inertia/collision/mesh_bvh.h"
#include "inertia/geometry/bounds.h"
#include "renderer.h"

namespace inertia::viewer {

namespace {

const char* kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aColor;
uniform mat4 uViewProj;
out vec3 vColor;
void main() {
  gl_Position = uViewProj * vec4(aPosition, 1.0);
  vColor = aColor;
}
)";

const char* kLineFragment = R"(#version 330 core
in vec3 vColor;
out vec4 fragColor;
void main() { fragColor = vec4(vColor, 1.0); }
)";

const Eigen::Vector3f kPoint(0.95f, 0.1f, 0.1f);
const Eigen::Vector3f kNormal(1.0f, 0.85f, 0.1f);
const Eigen::Vector3f kSpeculative(0.5f, 0.5f, 0.5f);
const Eigen::Vector3f kAwakeBox(0.1f, 0.85f, 0.9f);
const Eigen::Vector3f kSleepingBox(0.15f, 0.2f, 0.55f);
const Eigen::Vector3f kLinear(0.1f, 0.8f, 0.2f);
const Eigen::Vector3f kAngular(0.85f, 0.2f, 0.85f);
const Eigen::Vector3f kTreeLeaf(0.6f, 0.6f, 0.6f);
const Eigen::Vector3f kJointBone(0.9f, 0.9f, 0.9f);
const Eigen::Vector3f kJointAxis(0.2f, 0.9f, 0.9f);
const Eigen::Vector3f kJointLimit(1.0f, 0.55f, 0.1f);
const Eigen::Vector3f kJointBroken(0.9f, 0.15f, 0.1f);

void cross(DebugLines& out, const Vec3& p, Real size, const Eigen::Vector3f& color) {
  for (int k = 0; k < 3; ++k) {
    const Vec3 d = size * Vec3::Unit(k);
    out.add(p - d, p + d, color);
  }
}

// The 12 edges of box `b`, posed by `pose` (the identity for world boxes).
void box(DebugLines& out, const Aabb& b, const Eigen::Vector3f& color,
         const Transform& pose = Transform{}) {
  auto corner = [&](int i) {
    return pose.apply(Vec3(i & 1 ? b.upper.x() : b.lower.x(), i & 2 ? b.upper.y() : b.lower.y(),
                           i & 4 ? b.upper.z() : b.lower.z()));
  };
  // The 12 edges join corners differing in one bit.
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4})
      if (!(i & bit)) out.add(corner(i), corner(i | bit), color);
}

// A joint: bones from the bodies' centres to the anchors, the anchors, its axis, a hinge's
// limits as two spokes about the axis; a broken or disabled joint as red anchors only.
void joint(DebugLines& out, const RigidBodySystem& rb, JointId j, Real scale) {
  const Transform a = rb.jointFrameA(j), b = rb.jointFrameB(j);
  const Real size = Real(0.06) * scale;
  if (!rb.isJointEnabled(j)) {
    cross(out, a.p, size, kJointBroken);
    cross(out, b.p, size, kJointBroken);
    return;
  }
  if (const BodyId body = rb.jointBodyA(j); !body.isNull())
    out.add(rb.centerOfMass(body), a.p, kJointBone);
  out.add(rb.centerOfMass(rb.jointBodyB(j)), b.p, kJointBone);
  cross(out, a.p, size, kJointBone);
  const JointType type = rb.jointType(j);
  if (type == JointType::Weld || type == JointType::Distance) return;
  const Vec3 axis = a.rotate(Vec3::UnitX());
  out.add(a.p - Real(0.25) * scale * axis, a.p + Real(0.25) * scale * axis, kJointAxis);
  const JointAxis& angle = rb.jointAxis(j, 3);
  if (type == JointType::Hinge && angle.limits)
    for (Real limit : {angle.limits->lower, angle.limits->upper}) {
      const Vec3 spoke = a.rotate(Vec3(0, std::cos(limit), std::sin(limit)));
      out.add(a.p, a.p + Real(0.3) * scale * spoke, kJointLimit);
    }
}

}  // namespace

void DebugLines::add(const Vec3& a, const Vec3& b, const Eigen::Vector3f& color) {
  vertices.insert(vertices.end(),
                  {float(a.x()), float(a.y()), float(a.z()), color.x(), color.y(), color.z(),
                   float(b.x()), float(b.y()), float(b.z()), color.x(), color.y(), color.z()});
}

void buildDebugLines(const World& world, const DebugDrawFlags& flags, Real scale, DebugLines& out) {
  const RigidBodySystem& rb = world.rigidBodies();
  if (flags.contacts) {
    const Real slop = world.settings().contact.linearSlop;
    for (const ContactInfo& c : rb.contacts()) {
      for (int k = 0; k < c.manifold.pointCount; ++k) {
        const ContactPoint& p = c.manifold.points[std::size_t(k)];
        const bool touching = p.separation <= slop;
        if (!touching && !flags.speculative) continue;
        const Vec3 mid = Real(0.5) * (p.pointA + p.pointB);
        cross(out, mid, Real(0.08) * scale, touching ? kPoint : kSpeculative);
        if (touching) out.add(mid, mid + scale * c.manifold.normal, kNormal);
      }
    }
  }
  if (flags.joints)
    for (JointId j : rb.joints()) joint(out, rb, j, scale);
  if (flags.broadPhaseTree) {
    const std::vector<BroadPhaseNode> nodes = rb.broadPhaseNodes();
    int height = 1;
    for (const BroadPhaseNode& n : nodes) height = std::max(height, n.height);
    for (const BroadPhaseNode& n : nodes) {
      // Leaves grey; inner nodes from green (low) to orange (the root).
      const float t = float(n.height) / float(height);
      const Eigen::Vector3f color = n.height == 0 ? kTreeLeaf
                                                  : Eigen::Vector3f(0.2f + 0.8f * t, 0.8f, 0.2f);
      box(out, n.box, color);
    }
  }
  if (flags.meshBvh) {
    for (BodyId body : rb.bodies())
      for (ShapeId shape : rb.shapes(body)) {
        const MeshBvh* bvh = rb.collider(shape).meshBvh();
        if (!bvh || bvh->nodes().empty()) continue;
        const Transform pose = rb.shapeTransform(shape);
        const auto& nodes = bvh->nodes();
        // Depth-first layout: an inner node's first child follows it, the second is `index`.
        std::vector<std::pair<std::uint32_t, int>> stack{{0u, 0}};
        while (!stack.empty()) {
          const auto [i, depth] = stack.back();
          stack.pop_back();
          const MeshBvh::Node& node = nodes[i];
          const float t = float(depth) / float(std::max(flags.bvhDepth, 1));
          box(out, Aabb{node.lower, node.upper}, Eigen::Vector3f(1.0f, 0.3f + 0.6f * t, 0.2f),
              pose);
          if (node.isLeaf() || depth >= flags.bvhDepth) continue;
          stack.emplace_back(node.index, depth + 1);
          stack.emplace_back(i + 1, depth + 1);
        }
      }
  }
  if (!flags.aabbs && !flags.velocities && !flags.centersOfMass) return;
  for (BodyId body : rb.bodies()) {
    const bool dynamic = rb.type(body) == BodyType::Dynamic;
    if (flags.aabbs) {
      const Eigen::Vector3f& color = rb.isAwake(body) || !dynamic ? kAwakeBox : kSleepingBox;
      for (ShapeId shape : rb.shapes(body)) {
        const Shape& s = rb.collider(shape).shape();
        if (s.type() == ShapeType::Plane) continue;  // unbounded
        const Aabb b = worldBounds(s, rb.shapeTransform(shape));
        if (b.isValid() && b.upper.allFinite() && b.lower.allFinite()) box(out, b, color);
      }
    }
    if (!dynamic) continue;
    const Vec3 com = rb.centerOfMass(body);
    if (flags.centersOfMass) cross(out, com, Real(0.25) * scale, Eigen::Vector3f(1, 1, 1));
    if (flags.velocities) {
      out.add(com, com + Real(0.1) * rb.linearVelocity(body), kLinear);
      out.add(com, com + Real(0.1) * rb.angularVelocity(body), kAngular);
    }
  }
}

LineRenderer::LineRenderer() {
  program_ = linkProgram(kLineVertex, kLineFragment);
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &vbo_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<void*>(3 * sizeof(float)));
  glBindVertexArray(0);
}

LineRenderer::~LineRenderer() {
  glDeleteVertexArrays(1, &vao_);
  glDeleteBuffers(1, &vbo_);
  glDeleteProgram(program_);
}

void LineRenderer::draw(const DebugLines& lines, const Eigen::Matrix4f& viewProj) {
  if (lines.vertices.empty()) return;
  glEnable(GL_DEPTH_TEST);
  glUseProgram(program_);
  glUniformMatrix4fv(glGetUniformLocation(program_, "uViewProj"), 1, GL_FALSE, viewProj.data());
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(lines.vertices.size() * sizeof(float)),
               lines.vertices.data(), GL_STREAM_DRAW);
  glDrawArrays(GL_LINES, 0, GLsizei(lines.vertices.size() / 6));
  glBindVertexArray(0);
  glUseProgram(0);
}

}  // namespace inertia::viewer
