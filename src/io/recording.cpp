#include "inertia/io/recording.h"

#include <stdexcept>
#include <type_traits>

namespace inertia::io {

void appendReal(std::string& out, Real x) {
  constexpr const char* kFormat = std::is_same_v<Real, float> ? "%.9g" : "%.17g";
  char buffer[32];
  int n = std::snprintf(buffer, sizeof buffer, kFormat, double(x));
  out.append(buffer, std::size_t(n));
}

BodyRecorder::BodyRecorder(const std::filesystem::path& file) : path_(file) {
  file_ = std::fopen(file.c_str(), "wb");
  if (!file_) throw std::runtime_error(file.string() + ": cannot be opened for writing");
  std::fwrite(kHeader.data(), 1, kHeader.size(), file_);
  std::fputc('\n', file_);
}

BodyRecorder::~BodyRecorder() {
  if (file_) std::fclose(file_);
}

void BodyRecorder::write(Real time, std::string_view body, const Transform& pose, const Vec3& v,
                         const Vec3& w) {
  line_.clear();
  appendReal(line_, time);
  line_ += ',';
  line_ += body;
  const Real values[] = {pose.p.x(), pose.p.y(), pose.p.z(), pose.q.w(), pose.q.x(),
                         pose.q.y(), pose.q.z(), v.x(),      v.y(),      v.z(),
                         w.x(),      w.y(),      w.z()};
  for (Real x : values) {
    line_ += ',';
    appendReal(line_, x);
  }
  line_ += '\n';
  std::fwrite(line_.data(), 1, line_.size(), file_);
}

void BodyRecorder::close() {
  if (!file_) return;
  bool failed = std::ferror(file_) != 0;
  failed |= std::fclose(file_) != 0;
  file_ = nullptr;
  if (failed) throw std::runtime_error(path_.string() + ": write failed");
}

JointRecorder::JointRecorder(const std::filesystem::path& file) : path_(file) {
  file_ = std::fopen(file.c_str(), "wb");
  if (!file_) throw std::runtime_error(file.string() + ": cannot be opened for writing");
  std::fwrite(kHeader.data(), 1, kHeader.size(), file_);
  std::fputc('\n', file_);
}

JointRecorder::~JointRecorder() {
  if (file_) std::fclose(file_);
}

void JointRecorder::write(Real time, std::string_view joint, bool broken, const Vec3& force,
                          const Vec3& torque, const JointError& error) {
  line_.clear();
  appendReal(line_, time);
  line_ += ',';
  line_ += joint;
  line_ += broken ? ",1" : ",0";
  const Real values[] = {force.x(),  force.y(),  force.z(),      torque.x(),
                         torque.y(), torque.z(), error.position, error.angle};
  for (Real x : values) {
    line_ += ',';
    appendReal(line_, x);
  }
  line_ += '\n';
  std::fwrite(line_.data(), 1, line_.size(), file_);
}

void JointRecorder::close() {
  if (!file_) return;
  bool failed = std::ferror(file_) != 0;
  failed |= std::fclose(file_) != 0;
  file_ = nullptr;
  if (failed) throw std::runtime_error(path_.string() + ": write failed");
}

ParticleRecorder::ParticleRecorder(const std::filesystem::path& file) : path_(file) {
  file_ = std::fopen(file.c_str(), "wb");
  if (!file_) throw std::runtime_error(file.string() + ": cannot be opened for writing");
  std::fwrite(kHeader.data(), 1, kHeader.size(), file_);
  std::fputc('\n', file_);
}

ParticleRecorder::~ParticleRecorder() {
  if (file_) std::fclose(file_);
}

void ParticleRecorder::write(Real time, std::string_view system, const ParticlePool& pool) {
  const auto x = pool.positions();
  const auto v = pool.velocities();
  const auto ids = pool.ids();
  const auto age = pool.ages();
  for (std::size_t i = 0; i < pool.size(); ++i) {
    buffer_.clear();
    appendReal(buffer_, time);
    buffer_ += ',';
    buffer_ += system;
    buffer_ += ',';
    buffer_ += std::to_string(ids[i]);
    for (int k = 0; k < 3; ++k) (buffer_ += ','), appendReal(buffer_, x[3 * i + k]);
    for (int k = 0; k < 3; ++k) (buffer_ += ','), appendReal(buffer_, v[3 * i + k]);
    buffer_ += ',';
    appendReal(buffer_, age[i]);
    buffer_ += '\n';
    std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
  }
}

void ParticleRecorder::close() {
  if (!file_) return;
  bool failed = std::ferror(file_) != 0;
  failed |= std::fclose(file_) != 0;
  file_ = nullptr;
  if (failed) throw std::runtime_error(path_.string() + ": write failed");
}

DeformableRecorder::DeformableRecorder(const std::filesystem::path& file) : path_(file) {
  file_ = std::fopen(file.c_str(), "wb");
  if (!file_) throw std::runtime_error(file.string() + ": cannot be opened for writing");
  std::fwrite(kHeader.data(), 1, kHeader.size(), file_);
  std::fputc('\n', file_);
}

DeformableRecorder::~DeformableRecorder() {
  if (file_) std::fclose(file_);
}

void DeformableRecorder::write(Real time, const Deformable& d) {
  const auto x = d.positions();
  const auto v = d.velocities();
  for (std::size_t i = 0; i < d.vertexCount(); ++i) {
    buffer_.clear();
    appendReal(buffer_, time);
    buffer_ += ',';
    buffer_ += d.name();
    buffer_ += ',';
    buffer_ += std::to_string(i);
    for (int k = 0; k < 3; ++k) (buffer_ += ','), appendReal(buffer_, x[3 * i + std::size_t(k)]);
    for (int k = 0; k < 3; ++k) (buffer_ += ','), appendReal(buffer_, v[3 * i + std::size_t(k)]);
    buffer_ += '\n';
    std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
  }
}

void DeformableRecorder::close() {
  if (!file_) return;
  bool failed = std::ferror(file_) != 0;
  failed |= std::fclose(file_) != 0;
  file_ = nullptr;
  if (failed) throw std::runtime_error(path_.string() + ": write failed");
}

}  // namespace inertia::io
