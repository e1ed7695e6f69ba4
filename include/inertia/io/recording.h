// Recording simulation state as CSV (DESIGN.md section 6).
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "inertia/core/types.h"
#include "inertia/deformable/deformable.h"
#include "inertia/dynamics/joint.h"
#include "inertia/particles/pool.h"

namespace inertia::io {

/// Formats a value with enough digits to round-trip: %.9g for float, %.17g for double.
/// Appends to `out` without allocating once `out` has grown.
void appendReal(std::string& out, Real x);

/// Writes `time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz` rows, one per body per recorded
/// step. Output is buffered and byte-for-byte deterministic.
class BodyRecorder {
 public:
  /// Opens `file` for writing and writes the header. Throws std::runtime_error naming the file
  /// when it cannot be opened.
  explicit BodyRecorder(const std::filesystem::path& file);
  ~BodyRecorder();
  BodyRecorder(const BodyRecorder&) = delete;
  BodyRecorder& operator=(const BodyRecorder&) = delete;

  static constexpr std::string_view kHeader =
      "time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";

  /// One row: `body` is the body's name (its index when unnamed); `v` (m/s) and `w` (rad/s) are
  /// the linear velocity of the centre of mass and the angular velocity, in world coordinates.
  void write(Real time, std::string_view body, const Transform& pose, const Vec3& v, const Vec3& w);

  /// Flushes to disk; throws std::runtime_error when the write failed (disk full, ...).
  void close();

 private:
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::string line_;
};

/// Writes `time,system,id,px,py,pz,vx,vy,vz,age` rows, one per live particle per recorded
/// step, in pool order (oldest first).
class ParticleRecorder {
 public:
  /// Opens `file` and writes the header; throws std::runtime_error naming the file on failure.
  explicit ParticleRecorder(const std::filesystem::path& file);
  ~ParticleRecorder();
  ParticleRecorder(const ParticleRecorder&) = delete;
  ParticleRecorder& operator=(const ParticleRecorder&) = delete;

  static constexpr std::string_view kHeader = "time,system,id,px,py,pz,vx,vy,vz,age";

  /// Every live particle of `pool` at `time`; `system` is the system's name.
  void write(Real time, std::string_view system, const ParticlePool& pool);
  /// Flushes; throws std::runtime_error when the write failed.
  void close();

 private:
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::string buffer_;
};

/// Writes `time,joint,broken,fx,fy,fz,tx,ty,tz,position_error,angle_error` rows, one per joint
/// per recorded step.
class JointRecorder {
 public:
  /// Opens `file` and writes the header; throws std::runtime_error naming the file on failure.
  explicit JointRecorder(const std::filesystem::path& file);
  ~JointRecorder();
  JointRecorder(const JointRecorder&) = delete;
  JointRecorder& operator=(const JointRecorder&) = delete;

  static constexpr std::string_view kHeader =
      "time,joint,broken,fx,fy,fz,tx,ty,tz,position_error,angle_error";

  /// One row: `joint` is the joint's name (its index when unnamed); `force` (N) and `torque`
  /// (N m) are the constraint's on body B in world axes (RigidBodySystem::jointForce and
  /// jointTorque); `error` is RigidBodySystem::jointError (m and rad).
  void write(Real time, std::string_view joint, bool broken, const Vec3& force, const Vec3& torque,
             const JointError& error);
  /// Flushes; throws std::runtime_error when the write failed.
  void close();

 private:
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::string line_;
};

/// Writes `time,deformable,vertex,px,py,pz,vx,vy,vz` rows, one per vertex per recorded step.
class DeformableRecorder {
 public:
  /// Opens `file` and writes the header; throws std::runtime_error naming the file on failure.
  explicit DeformableRecorder(const std::filesystem::path& file);
  ~DeformableRecorder();
  DeformableRecorder(const DeformableRecorder&) = delete;
  DeformableRecorder& operator=(const DeformableRecorder&) = delete;

  static constexpr std::string_view kHeader = "time,deformable,vertex,px,py,pz,vx,vy,vz";

  /// Every vertex of `deformable` at `time`, in vertex order; the column `deformable` is its name.
  void write(Real time, const Deformable& deformable);
  /// Flushes; throws std::runtime_error when the write failed.
  void close();

 private:
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::string buffer_;
};

}  // namespace inertia::io
