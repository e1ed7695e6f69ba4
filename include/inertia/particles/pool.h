// The particle pool: fixed capacity, structure of arrays, live particles packed at the front.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "inertia/core/types.h"

namespace inertia {

/// Storage of a particle system: one array per attribute (structure of arrays), sized once to
/// the capacity so that stepping never allocates. The live particles are the first size() of
/// every array. A particle that dies is removed by a stable compaction, so live particles keep
/// their order (oldest first, which is also increasing id) and the storage of the dead is
/// reused by the next ones emitted: the reuse order is deterministic.
///
/// Vector attributes (position, velocity, colour) hold 3 consecutive Reals per particle, so a
/// whole attribute is one contiguous span an ode integrator can advance in place.
class ParticlePool {
 public:
  /// Throws InvalidArgument unless 1 <= capacity <= 2^31.
  explicit ParticlePool(std::size_t capacity);

  std::size_t capacity() const { return capacity_; }
  std::size_t size() const { return size_; }
  bool full() const { return size_ == capacity_; }

  /// Adds a user attribute (one Real per particle, zero for new particles), kept in step with
  /// the others through compaction; returns its index for attribute(). Only before particles
  /// exist; throws InvalidArgument otherwise or for a duplicate name.
  std::size_t addAttribute(const std::string& name);
  /// The index of a user attribute by name, or throws InvalidArgument.
  std::size_t attributeIndex(const std::string& name) const;
  std::span<Real> attribute(std::size_t index) { return {user_.at(index).data(), size_}; }
  std::span<const Real> attribute(std::size_t index) const { return {user_.at(index).data(), size_}; }

  // Live data, size() particles (3 * size() Reals for vector attributes).
  std::span<Real> positions() { return {position_.data(), 3 * size_}; }       ///< m
  std::span<Real> velocities() { return {velocity_.data(), 3 * size_}; }      ///< m/s
  std::span<Real> masses() { return {mass_.data(), size_}; }                  ///< kg
  std::span<Real> ages() { return {age_.data(), size_}; }                     ///< s
  std::span<Real> lifetimes() { return {lifetime_.data(), size_}; }           ///< s
  std::span<Real> radii() { return {radius_.data(), size_}; }                 ///< m
  std::span<Real> colors() { return {color_.data(), 3 * size_}; }             ///< rgb, 0..1
  std::span<const Real> positions() const { return {position_.data(), 3 * size_}; }
  std::span<const Real> velocities() const { return {velocity_.data(), 3 * size_}; }
  std::span<const Real> masses() const { return {mass_.data(), size_}; }
  std::span<const Real> ages() const { return {age_.data(), size_}; }
  std::span<const Real> lifetimes() const { return {lifetime_.data(), size_}; }
  std::span<const Real> radii() const { return {radius_.data(), size_}; }
  std::span<const Real> colors() const { return {color_.data(), 3 * size_}; }
  /// Unique ids, increasing along the pool (a particle's id never changes).
  std::span<const std::uint64_t> ids() const { return {id_.data(), size_}; }

  Vec3 position(std::size_t i) const { return Eigen::Map<const Vec3>(&position_[3 * i]); }
  Vec3 velocity(std::size_t i) const { return Eigen::Map<const Vec3>(&velocity_[3 * i]); }

  /// A new particle's initial state.
  struct Spawn {
    Vec3 position = Vec3::Zero();  ///< m
    Vec3 velocity = Vec3::Zero();  ///< m/s
    Real mass = Real(1e-3);        ///< kg, > 0
    Real lifetime = 1;             ///< s, > 0 (infinity: lives for ever)
    Real radius = Real(0.01);      ///< m, >= 0
    Vec3 color = Vec3::Ones();     ///< rgb, 0..1
    Real age = 0;                  ///< s
  };
  /// Appends a particle; returns false (and adds nothing) when the pool is full.
  /// The values are trusted: emitters produce valid ones (checked where settings enter).
  bool add(const Spawn& s);

  /// Removes every particle whose flag is set (flags has size() entries), keeping the order of
  /// the others. Returns the number removed. Linear in size(), allocation-free.
  std::size_t removeFlagged(std::span<const std::uint8_t> flags);

  /// Removes every particle.
  void clear() { size_ = 0; }

 private:
  std::size_t capacity_ = 0, size_ = 0;
  std::uint64_t nextId_ = 0;
  std::vector<Real> position_, velocity_, mass_, age_, lifetime_, radius_, color_;
  std::vector<std::uint64_t> id_;
  std::vector<std::string> userNames_;
  std::vector<std::vector<Real>> user_;
};

}  // namespace inertia
