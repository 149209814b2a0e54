// grip's one error type: every public entry point validates its input and throws grip::Error
// naming the offending field. A call that throws leaves the world exactly as it was.
#pragma once

#include <stdexcept>
#include <string>

#include "core/math.hpp"

namespace grip {

class Error : public std::runtime_error {
 public:
  Error(std::string field, const std::string& what)
      : std::runtime_error(field.empty() ? what : field + ": " + what), field_(std::move(field)) {}
  // The name of the offending field or argument, e.g. "BodyDef.mass".
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// Validation helpers used at the public boundary.
inline void requireFinite(double x, const char* field) {
  if (!std::isfinite(x)) throw Error(field, "must be finite (got " + std::to_string(x) + ")");
}
inline void requireFinite(const Vec3& v, const char* field) {
  if (!v.allFinite()) throw Error(field, "must be finite");
}
inline void requireFinite(const Quat& q, const char* field) {
  if (!q.coeffs().allFinite()) throw Error(field, "must be finite");
  if (q.norm() < 1e-9) throw Error(field, "must be a non-zero quaternion");
}
inline void requirePositive(double x, const char* field) {
  requireFinite(x, field);
  if (!(x > 0.0)) throw Error(field, "must be positive (got " + std::to_string(x) + ")");
}
inline void requireNonNegative(double x, const char* field) {
  requireFinite(x, field);
  if (x < 0.0) throw Error(field, "must not be negative (got " + std::to_string(x) + ")");
}

}  // namespace grip
