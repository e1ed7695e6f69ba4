// Shapes: the primitives, the ShapeType tag, and the Shape value that holds any of them.
//
// Why a tagged value (a std::variant behind a small class) and not a class hierarchy: the
// collision layer dispatches on *pairs* of shapes through a [ShapeType][ShapeType] table of free
// functions (Box2D v3's b2Manifold table, MuJoCo's collision table). A virtual hierarchy gives
// single dispatch only and invites one subclass per pair; a tag gives an array index. The
// primitives are plain aggregates stored inline (no allocation, cheap to copy); the large,
// immutable shapes (hull, mesh, height field, compound) are held by shared_ptr<const T>, so many
// bodies can share one mesh and copying a Shape never copies vertex arrays.
#pragma once

#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "inertia/core/types.h"
#include "inertia/geometry/height_field.h"
#include "inertia/geometry/hull.h"
#include "inertia/geometry/mesh.h"

namespace inertia {

/// The half-space {x : normal . x <= offset} (solid below the plane). Static bodies only.
/// A Shape stores it with a unit normal (normal and offset divided by |normal|, same half-space).
struct Plane {
  Vec3 normal = Vec3::UnitY();  ///< Outward normal (unit once in a Shape).
  Real offset = 0;              ///< Signed distance of the plane from the origin along normal (m).
};

/// A ball centred at the local origin.
struct Sphere {
  Real radius = Real(0.5);  ///< Radius (m), > 0.
};

/// The points within `radius` of the segment from (0, -halfHeight, 0) to (0, halfHeight, 0):
/// a cylinder capped by two hemispheres, axis along local y.
struct Capsule {
  Real radius = Real(0.5);      ///< Radius (m), > 0.
  Real halfHeight = Real(0.5);  ///< Half the length of the core segment (m), > 0.
};

/// A box centred at the local origin, axis-aligned in its local frame.
struct Box {
  Vec3 halfExtents = Vec3::Constant(Real(0.5));  ///< Half the side lengths (m), each > 0.
};

/// A solid circular cylinder centred at the local origin, axis along local y.
struct Cylinder {
  Real radius = Real(0.5);      ///< Radius (m), > 0.
  Real halfHeight = Real(0.5);  ///< Half the height (m), > 0.
};

class Compound;

namespace detail {
template <class T>
inline constexpr bool kIsSharedPtr = false;
template <class T>
inline constexpr bool kIsSharedPtr<std::shared_ptr<T>> = true;
}  // namespace detail

/// The kind of a Shape; indexes the collision layer's pair table. Order is fixed (the index of
/// the alternative in Shape's variant).
enum class ShapeType : std::uint8_t {
  Plane,
  Sphere,
  Capsule,
  Box,
  Cylinder,
  Hull,
  Mesh,
  HeightField,
  Compound,
};
/// Number of shape types: the size of a [ShapeType][ShapeType] table.
inline constexpr int kShapeTypeCount = 9;

/// Lower-case name of a shape type ("box", "hull", ...), as in scene files.
const char* shapeTypeName(ShapeType type);
/// True for the shapes with a support function (sphere, capsule, box, cylinder, hull).
constexpr bool isConvex(ShapeType t) {
  return t == ShapeType::Sphere || t == ShapeType::Capsule || t == ShapeType::Box ||
         t == ShapeType::Cylinder || t == ShapeType::Hull;
}

/// Throw InvalidArgument naming the bad value unless the primitive is valid: sizes positive and
/// finite, plane normal finite and non-zero, offset finite.
void validate(const Plane& plane);
void validate(const Sphere& sphere);
void validate(const Capsule& capsule);
void validate(const Box& box);
void validate(const Cylinder& cylinder);

/// Any shape, as a small value: a ShapeType tag plus the data. Construction validates
/// (hulls, meshes, height fields and compounds validate when they are built), so a Shape is
/// always valid. Read it with type() and get<T>() / getIf<T>(), or visit().
class Shape {
 public:
  Shape(const Plane& plane);  // NOLINT(google-explicit-constructor): Shapes convert implicitly
  Shape(const Sphere& sphere);
  Shape(const Capsule& capsule);
  Shape(const Box& box);
  Shape(const Cylinder& cylinder);
  Shape(ConvexHull hull);
  Shape(std::shared_ptr<const ConvexHull> hull);
  Shape(TriangleMesh mesh);
  Shape(std::shared_ptr<const TriangleMesh> mesh);
  Shape(HeightField field);
  Shape(std::shared_ptr<const HeightField> field);
  Shape(Compound compound);
  Shape(std::shared_ptr<const Compound> compound);

  ShapeType type() const { return static_cast<ShapeType>(data_.index()); }

  /// The shape as a T (Plane, Sphere, Capsule, Box, Cylinder, ConvexHull, TriangleMesh,
  /// HeightField or Compound), or nullptr when it is another type.
  template <class T>
  const T* getIf() const {
    if constexpr (std::is_same_v<T, ConvexHull> || std::is_same_v<T, TriangleMesh> ||
                  std::is_same_v<T, HeightField> || std::is_same_v<T, Compound>) {
      const auto* p = std::get_if<std::shared_ptr<const T>>(&data_);
      return p ? p->get() : nullptr;
    } else {
      return std::get_if<T>(&data_);
    }
  }
  /// The shape as a T; throws InvalidArgument when it is another type.
  template <class T>
  const T& get() const {
    const T* p = getIf<T>();
    if (!p) throwWrongType();
    return *p;
  }
  /// Calls f with the shape's data as a const reference to its concrete type.
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(
        [&f](const auto& alt) -> decltype(auto) {
          if constexpr (detail::kIsSharedPtr<std::decay_t<decltype(alt)>>) {
            return std::forward<F>(f)(*alt);
          } else {
            return std::forward<F>(f)(alt);
          }
        },
        data_);
  }

 private:
  [[noreturn]] void throwWrongType() const;

  std::variant<Plane, Sphere, Capsule, Box, Cylinder, std::shared_ptr<const ConvexHull>,
               std::shared_ptr<const TriangleMesh>, std::shared_ptr<const HeightField>,
               std::shared_ptr<const Compound>>
      data_;
};

/// One child of a compound: a shape and its pose relative to the compound's frame.
struct CompoundChild {
  Shape shape;
  Transform transform;  ///< Child local -> compound local.
};

/// Several shapes rigidly joined, each with its own pose. Immutable once built.
class Compound {
 public:
  /// Throws InvalidArgument for no children, or a child transform that is not finite or whose
  /// quaternion is not unit length (|q| within 1e-4 of 1; it is then renormalised).
  explicit Compound(std::vector<CompoundChild> children);
  const std::vector<CompoundChild>& children() const { return children_; }

 private:
  std::vector<CompoundChild> children_;
};

}  // namespace inertia
