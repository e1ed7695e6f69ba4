#include "convert.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <regex>
#include <utility>

namespace inertia::python {

void argumentError(const std::string& arg, const std::string& what) {
  throw py::value_error(arg + ": " + what);
}

namespace {

// C++ fields the Python API names otherwise (its keyword arguments), as the library's messages
// spell them.
constexpr std::array<std::pair<const char*, const char*>, 4> kRenamed{{
    {R"(BodySettings::linearVelocity)", "velocity"},
    {R"(drive\.targetPosition)", "drive.target"},
    {R"(\b\w+Settings::?\s*pose\b)", "position and orientation"},
    {R"(RopeSettings: from and to)", "start and end"},
}};

std::string snakeCase(const std::string& name) {
  std::string out;
  for (char c : name) {
    if (std::isupper(static_cast<unsigned char>(c))) {
      out += '_';
      out += char(std::tolower(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out;
}

// Applies `f` to each match of `re` in `s`, keeping the text between them.
template <class F>
std::string replaceEach(const std::string& s, const std::regex& re, F f) {
  std::string out;
  auto last = s.cbegin();
  for (std::sregex_iterator it(s.begin(), s.end(), re), end; it != end; ++it) {
    out.append(last, (*it)[0].first);
    out += f(*it);
    last = (*it)[0].second;
  }
  return out.append(last, s.cend());
}

// The translation of text outside quotes (a quoted name or path is the user's own).
std::string pythonNames(std::string s) {
  for (const auto& [cpp, python] : kRenamed) s = std::regex_replace(s, std::regex(cpp), python);
  // "XSettings::field" and "XSettings: field": the struct of a create_* call's arguments.
  s = std::regex_replace(s, std::regex(R"(\b[A-Z]\w*Settings(::|: ))"), "");
  s = std::regex_replace(s, std::regex(R"(\b([A-Z]\w*)::)"), "$1.");
  // camelCase, except a file's name (after a slash, or before ".obj", the one mesh format
  // whose path the library's InvalidArgument messages may carry).
  static const std::regex camel(R"(\b[a-z][a-z0-9]*(?:[A-Z][a-z0-9]*)+\b)");
  return replaceEach(s, camel, [&s](const std::smatch& m) {
    const auto begin = std::size_t(m.position(0)), end = begin + std::size_t(m.length(0));
    const bool path = (begin > 0 && s[begin - 1] == '/') ||
                      (end + 4 <= s.size() && s.compare(end, 4, ".obj") == 0);
    return path ? m.str() : snakeCase(m.str());
  });
}

}  // namespace

std::string pythonMessage(const std::string& what) {
  std::string out;
  std::size_t i = 0;
  while (i < what.size()) {
    // A quote opens after a space or a bracket; an apostrophe inside a word ("a link's") does not.
    std::size_t quote = what.find_first_of("'\"", i);
    while (quote != std::string::npos && quote > 0 &&
           std::isalnum(static_cast<unsigned char>(what[quote - 1])))
      quote = what.find_first_of("'\"", quote + 1);
    if (quote == std::string::npos) return out + pythonNames(what.substr(i));
    const std::size_t close = what.find(what[quote], quote + 1);
    out += pythonNames(what.substr(i, quote - i));
    const std::size_t next = close == std::string::npos ? what.size() : close + 1;
    out.append(what, quote, next - quote);
    i = next;
  }
  return out;
}

namespace {

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// Any array-like as a C-contiguous array of Reals; ValueError naming `arg` when it holds
// something that is not a number.
RealArray asReals(py::handle value, const char* arg) {
  // NumPy would read None as NaN.
  if (value.is_none()) argumentError(arg, "expected numbers, got None");
  // forcecast: ints and float64 are accepted and rounded to Real.
  RealArray a = RealArray::ensure(value);
  if (!a)
    argumentError(arg, "expected numbers (a regular array of them), got " +
                           std::string(py::str(py::type::of(value))));
  return a;
}

}  // namespace

void toReals(py::handle value, const char* arg, Real* out, std::size_t n) {
  RealArray a = asReals(value, arg);
  if (a.ndim() != 1 || std::size_t(a.shape(0)) != n)
    argumentError(arg, "expected " + std::to_string(n) + " numbers, got shape " + shapeText(a));
  std::copy_n(a.data(), n, out);
}

Vec3 toVec3(py::handle value, const char* arg) {
  Vec3 v;
  toReals(value, arg, v.data(), 3);
  return v;
}

Quat toQuat(py::handle value, const char* arg) {
  Real q[4];
  toReals(value, arg, q, 4);
  return Quat(q[0], q[1], q[2], q[3]);
}

RealArray toRows(py::handle value, const char* arg, py::ssize_t cols) {
  RealArray a = asReals(value, arg);
  if (a.ndim() != 2 || (cols >= 0 && a.shape(1) != cols))
    argumentError(arg, "expected an array of shape (n, " +
                           (cols >= 0 ? std::to_string(cols) : std::string("m")) + "), got " +
                           shapeText(a));
  return a;
}

RealArray toMatrix(py::handle value, const char* arg, py::ssize_t rows, py::ssize_t cols) {
  RealArray a = toRows(value, arg, cols);
  if (a.shape(0) != rows)
    argumentError(arg, "expected an array of shape (" + std::to_string(rows) + ", " +
                           std::to_string(cols) + "), got " + shapeText(a));
  return a;
}

RealArray fromVec3(const Vec3& v) {
  RealArray a(3);
  std::copy_n(v.data(), 3, a.mutable_data());
  return a;
}

Real* put(const Vec3& v, Real* out) {
  out[0] = v.x(), out[1] = v.y(), out[2] = v.z();
  return out + 3;
}

Real* put(const Quat& q, Real* out) {
  out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
  return out + 4;
}

RealArray fromQuat(const Quat& q) {
  RealArray a(4);
  put(q, a.mutable_data());
  return a;
}

RealArray fromMat3(const Mat3& m) {
  RealArray a({3, 3});
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a.mutable_at(i, j) = m(i, j);
  return a;
}

void setAttributes(py::handle object, const py::kwargs& kwargs, const char* type) {
  for (auto [key, value] : kwargs) {
    const std::string name = py::str(key);
    // Only the class's properties are settable this way, not its methods.
    py::object attr = py::getattr(py::type::of(object), key, py::none());
    if (!py::isinstance(attr, py::module_::import("builtins").attr("property")))
      throw py::type_error(std::string(type) + ": unknown argument '" + name + "'");
    object.attr(key) = value;
  }
}

}  // namespace inertia::python
