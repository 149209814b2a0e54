// A 64-bit FNV-1a hash over the exact bits of values: bit-identical states give equal hashes.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

#include "core/math.hpp"

namespace grip {

class StateHash {
 public:
  void add(const void* data, size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) {
      h_ ^= b[i];
      h_ *= 1099511628211ull;
    }
  }
  void add(double x) {
    if (x == 0.0) x = 0.0;  // +0 and -0 are the same state
    add(&x, sizeof x);
  }
  void add(uint64_t x) { add(&x, sizeof x); }
  void add(const Vec3& v) { add(v.x()), add(v.y()), add(v.z()); }
  void add(const Quat& q) { add(q.w()), add(q.x()), add(q.y()), add(q.z()); }
  void add(const Transform& t) { add(t.p), add(t.q); }
  uint64_t value() const { return h_; }
  std::string hex() const;

 private:
  uint64_t h_ = 1469598103934665603ull;
};

inline std::string StateHash::hex() const {
  static const char* digits = "0123456789abcdef";
  std::string s(16, '0');
  for (int i = 0; i < 16; ++i) s[15 - i] = digits[(h_ >> (4 * i)) & 0xF];
  return s;
}

}  // namespace grip
