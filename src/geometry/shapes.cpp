#include "inertia/geometry/shapes.h"

#include <cmath>
#include <sstream>
#include <string>

#include "inertia/core/error.h"
#include "inertia/core/math.h"

namespace inertia {

// The variant's alternatives must be in ShapeType order: type() is the variant index.
static_assert(kShapeTypeCount == 9);

namespace {

std::string str(const Vec3& v) {
  std::ostringstream s;
  s << '[' << v.x() << ", " << v.y() << ", " << v.z() << ']';
  return s.str();
}

void requireSize(Real value, const char* what) {
  if (!(std::isfinite(value) && value > 0)) {
    std::ostringstream s;
    s << what << " must be positive and finite, got " << value;
    throw InvalidArgument(s.str());
  }
}

// Out of line and cold: building the message only on failure, and keeping GCC 12's
// -Warray-bounds false positive on inlined std::string concatenation out of the constructors.
[[noreturn, gnu::noinline, gnu::cold]] void throwNullShape(const char* what) {
  std::string message = "Shape: null ";
  message += what;
  throw InvalidArgument(message);
}

template <class T>
std::shared_ptr<const T> requireNonNull(std::shared_ptr<const T> p, const char* what) {
  if (p == nullptr) throwNullShape(what);
  return p;
}

}  // namespace

const char* shapeTypeName(ShapeType type) {
  switch (type) {
    case ShapeType::Plane:
      return "plane";
    case ShapeType::Sphere:
      return "sphere";
    case ShapeType::Capsule:
      return "capsule";
    case ShapeType::Box:
      return "box";
    case ShapeType::Cylinder:
      return "cylinder";
    case ShapeType::Hull:
      return "hull";
    case ShapeType::Mesh:
      return "mesh";
    case ShapeType::HeightField:
      return "heightfield";
    case ShapeType::Compound:
      return "compound";
  }
  return "unknown";
}

void validate(const Plane& plane) {
  require(allFinite(plane.normal), "Plane normal must be finite, got " + str(plane.normal));
  require(plane.normal.norm() > 0, "Plane normal must be non-zero (zero-length normal)");
  require(std::isfinite(plane.offset), "Plane offset must be finite");
}
void validate(const Sphere& sphere) { requireSize(sphere.radius, "Sphere radius"); }
void validate(const Capsule& capsule) {
  requireSize(capsule.radius, "Capsule radius");
  requireSize(capsule.halfHeight, "Capsule halfHeight");
}
void validate(const Box& box) {
  requireSize(box.halfExtents.x(), "Box halfExtents.x");
  requireSize(box.halfExtents.y(), "Box halfExtents.y");
  requireSize(box.halfExtents.z(), "Box halfExtents.z");
}
void validate(const Cylinder& cylinder) {
  requireSize(cylinder.radius, "Cylinder radius");
  requireSize(cylinder.halfHeight, "Cylinder halfHeight");
}

Shape::Shape(const Plane& plane) : data_(plane) {
  validate(plane);
  // Same half-space with a unit normal: n.x <= d  <=>  (n/|n|).x <= d/|n|.
  const Real len = plane.normal.norm();
  auto& p = std::get<Plane>(data_);
  p.normal = plane.normal / len;
  p.offset = plane.offset / len;
}
Shape::Shape(const Sphere& sphere) : data_(sphere) { validate(sphere); }
Shape::Shape(const Capsule& capsule) : data_(capsule) { validate(capsule); }
Shape::Shape(const Box& box) : data_(box) { validate(box); }
Shape::Shape(const Cylinder& cylinder) : data_(cylinder) { validate(cylinder); }
Shape::Shape(ConvexHull hull)
    : data_(std::shared_ptr<const ConvexHull>(std::make_shared<ConvexHull>(std::move(hull)))) {}
Shape::Shape(std::shared_ptr<const ConvexHull> hull)
    : data_(requireNonNull(std::move(hull), "hull")) {}
Shape::Shape(TriangleMesh mesh)
    : data_(std::shared_ptr<const TriangleMesh>(std::make_shared<TriangleMesh>(std::move(mesh)))) {}
Shape::Shape(std::shared_ptr<const TriangleMesh> mesh)
    : data_(requireNonNull(std::move(mesh), "mesh")) {}
Shape::Shape(HeightField field)
    : data_(std::shared_ptr<const HeightField>(std::make_shared<HeightField>(std::move(field)))) {}
Shape::Shape(std::shared_ptr<const HeightField> field)
    : data_(requireNonNull(std::move(field), "height field")) {}
Shape::Shape(Compound compound)
    : data_(std::shared_ptr<const Compound>(std::make_shared<Compound>(std::move(compound)))) {}
Shape::Shape(std::shared_ptr<const Compound> compound)
    : data_(requireNonNull(std::move(compound), "compound")) {}

void Shape::throwWrongType() const {
  throw InvalidArgument(std::string("Shape::get: the shape is a ") + shapeTypeName(type()) +
                        ", not the type asked for");
}

Compound::Compound(std::vector<CompoundChild> children) : children_(std::move(children)) {
  require(!children_.empty(), "Compound needs at least one child shape");
  for (std::size_t i = 0; i < children_.size(); ++i) {
    Transform& xf = children_[i].transform;
    const std::string where = "Compound child " + std::to_string(i) + ": ";
    require(allFinite(xf.p) && allFinite(xf.q), where + "transform is not finite");
    require(std::abs(xf.q.norm() - 1) <= Real(1e-4),
            where + "orientation is not a unit quaternion");
    xf.q.normalize();
  }
}

}  // namespace inertia
