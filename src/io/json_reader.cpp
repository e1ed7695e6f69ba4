#include "json_reader.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace inertia::io::detail {

namespace {

std::string show(double x) {
  std::ostringstream s;
  s.precision(10);
  s << x;
  return s.str();
}

// Levenshtein distance, for "did you mean" on unknown keys.
std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string typeName(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::object: return "an object";
    case Json::value_t::array: return "an array";
    case Json::value_t::string: return "a string";
    case Json::value_t::boolean: return "a boolean";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "a number";
    default: return "an unsupported value";
  }
}

void Node::fail(const std::string& reason) const {
  throw SceneError(*file_, pointer_.to_string(), reason);
}

void Node::requireObject(std::span<const std::string_view> allowed) const {
  if (!value_->is_object()) fail("expected an object, got " + typeName(*value_));
  for (const auto& item : value_->items()) {
    const std::string& key = item.key();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string reason = "unknown key \"" + key + "\"";
    std::string_view best;
    std::size_t bestDistance = 3;  // suggest only near misses
    for (std::string_view a : allowed) {
      std::size_t d = editDistance(key, a);
      if (d < bestDistance) best = a, bestDistance = d;
    }
    if (!best.empty()) reason += " (did you mean \"" + std::string(best) + "\"?)";
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    reason += "; allowed keys: " + list;
    throw SceneError(*file_, (pointer_ / key).to_string(), reason);
  }
}

bool Node::has(std::string_view key) const {
  return value_->is_object() && value_->contains(key);
}

Node Node::at(std::string_view key) const {
  if (!value_->is_object()) fail("expected an object, got " + typeName(*value_));
  auto it = value_->find(key);
  if (it == value_->end()) fail("missing required key \"" + std::string(key) + "\"");
  return Node(*it, pointer_ / std::string(key), *file_);
}

std::size_t Node::requireArray() const {
  if (!value_->is_array()) fail("expected an array, got " + typeName(*value_));
  return value_->size();
}

Node Node::at(std::size_t index) const {
  requireArray();
  if (index >= value_->size()) fail("index " + std::to_string(index) + " out of range");
  return Node((*value_)[index], pointer_ / index, *file_);
}

std::string Node::string() const {
  if (!value_->is_string()) fail("expected a string, got " + typeName(*value_));
  return value_->get<std::string>();
}

std::filesystem::path Node::path(const char* what) const {
  const std::filesystem::path relative = string();
  if (relative.empty()) fail(std::string("empty ") + what + " path");
  if (relative.is_absolute()) return relative;
  return std::filesystem::path(file()).parent_path() / relative;
}

bool Node::boolean() const {
  if (!value_->is_boolean()) fail("expected true or false, got " + typeName(*value_));
  return value_->get<bool>();
}

double Node::number() const {
  if (!value_->is_number()) fail("expected a number, got " + typeName(*value_));
  double x = value_->get<double>();
  if (!std::isfinite(x)) fail("expected a finite number, got " + show(x));
  return x;
}

double Node::number(double lo, double hi, bool openLo) const {
  double x = number();
  bool below = openLo ? !(x > lo) : x < lo;
  if (below || x > hi) {
    std::string range = (openLo ? "(" : "[") + show(lo) + ", " + show(hi) + "]";
    fail("value " + show(x) + " is out of range " + range);
  }
  return x;
}

long long Node::integer(long long lo, long long hi) const {
  if (!value_->is_number_integer()) {
    if (value_->is_number_float()) {
      double x = value_->get<double>();
      if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 9e15) {
        long long n = static_cast<long long>(x);
        if (n < lo || n > hi)
          fail("value " + std::to_string(n) + " is out of range [" + std::to_string(lo) + ", " +
               std::to_string(hi) + "]");
        return n;
      }
    }
    fail("expected an integer, got " +
         (value_->is_number() ? show(value_->get<double>()) : typeName(*value_)));
  }
  // Unsigned values beyond the signed range are out of range too.
  if (value_->is_number_unsigned() &&
      value_->get<unsigned long long>() > static_cast<unsigned long long>(hi))
    fail("value " + value_->dump() + " is out of range [" + std::to_string(lo) + ", " +
         std::to_string(hi) + "]");
  long long n = value_->get<long long>();
  if (n < lo || n > hi)
    fail("value " + std::to_string(n) + " is out of range [" + std::to_string(lo) + ", " +
         std::to_string(hi) + "]");
  return n;
}

Vec3 Node::vec3() const {
  if (requireArray() != 3) fail("expected an array of 3 numbers, got " + std::to_string(value_->size()) + " elements");
  return Vec3(Real(at(std::size_t(0)).number()), Real(at(std::size_t(1)).number()),
              Real(at(std::size_t(2)).number()));
}

Quat Node::quaternion() const {
  if (requireArray() != 4)
    fail("expected a quaternion [w, x, y, z], got " + std::to_string(value_->size()) + " elements");
  double c[4];
  for (std::size_t i = 0; i < 4; ++i) c[i] = at(i).number();
  double n = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
  if (std::fabs(n - 1) > 1e-3) fail("quaternion must have unit length, its norm is " + show(n));
  Quat q(static_cast<Real>(c[0]), static_cast<Real>(c[1]), static_cast<Real>(c[2]),
         static_cast<Real>(c[3]));
  q.normalize();
  return q;
}

}  // namespace inertia::io::detail
