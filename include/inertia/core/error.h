// The error type thrown at the API boundary for invalid input.
#pragma once

#include <stdexcept>
#include <string>

namespace inertia {

/// Thrown when a caller passes an invalid argument (negative mass, zero-size shape, NaN, ...).
/// The step itself never throws; invalid values are rejected where they enter.
class InvalidArgument : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Throws InvalidArgument with `what` unless `ok` holds.
inline void require(bool ok, const std::string& what) {
  if (!ok) throw InvalidArgument(what);
}

}  // namespace inertia
