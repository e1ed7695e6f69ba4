#include "inertia/particles/pool.h"

#include <algorithm>

#include "inertia/core/error.h"

namespace inertia {

ParticlePool::ParticlePool(std::size_t capacity) : capacity_(capacity) {
  require(capacity >= 1 && capacity <= (std::size_t(1) << 31),
          "ParticlePool: capacity must be in 1..2^31, got " + std::to_string(capacity));
  position_.resize(3 * capacity);
  velocity_.resize(3 * capacity);
  color_.resize(3 * capacity);
  mass_.resize(capacity);
  age_.resize(capacity);
  lifetime_.resize(capacity);
  radius_.resize(capacity);
  id_.resize(capacity);
}

std::size_t ParticlePool::addAttribute(const std::string& name) {
  require(size_ == 0, "ParticlePool::addAttribute: attributes must be added before particles");
  require(std::find(userNames_.begin(), userNames_.end(), name) == userNames_.end(),
          "ParticlePool::addAttribute: duplicate attribute \"" + name + "\"");
  userNames_.push_back(name);
  user_.emplace_back(capacity_, Real(0));
  return user_.size() - 1;
}

std::size_t ParticlePool::attributeIndex(const std::string& name) const {
  auto it = std::find(userNames_.begin(), userNames_.end(), name);
  require(it != userNames_.end(), "ParticlePool: no attribute \"" + name + "\"");
  return std::size_t(it - userNames_.begin());
}

bool ParticlePool::add(const Spawn& s) {
  if (size_ == capacity_) return false;
  const std::size_t i = size_++;
  for (int k = 0; k < 3; ++k) {
    position_[3 * i + k] = s.position[k];
    velocity_[3 * i + k] = s.velocity[k];
    color_[3 * i + k] = s.color[k];
  }
  mass_[i] = s.mass;
  age_[i] = s.age;
  lifetime_[i] = s.lifetime;
  radius_[i] = s.radius;
  id_[i] = nextId_++;
  for (auto& u : user_) u[i] = 0;
  return true;
}

std::size_t ParticlePool::removeFlagged(std::span<const std::uint8_t> flags) {
  // Stable compaction: one forward pass moving each survivor down over the dead.
  std::size_t out = 0;
  for (std::size_t i = 0; i < size_; ++i) {
    if (flags[i]) continue;
    if (out != i) {
      for (int k = 0; k < 3; ++k) {
        position_[3 * out + k] = position_[3 * i + k];
        velocity_[3 * out + k] = velocity_[3 * i + k];
        color_[3 * out + k] = color_[3 * i + k];
      }
      mass_[out] = mass_[i];
      age_[out] = age_[i];
      lifetime_[out] = lifetime_[i];
      radius_[out] = radius_[i];
      id_[out] = id_[i];
      for (auto& u : user_) u[out] = u[i];
    }
    ++out;
  }
  const std::size_t removed = size_ - out;
  size_ = out;
  return removed;
}

}  // namespace inertia
