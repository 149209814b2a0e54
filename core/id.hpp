// Value handles: an index into a slot array plus a generation that catches stale ids.
// The all-zero id is null; generation 0 is never handed out.
#pragma once

#include <cstdint>

namespace grip {

template <class Tag>
struct Id {
  uint32_t index = 0;
  uint32_t generation = 0;

  bool isNull() const { return generation == 0; }
  friend bool operator==(Id a, Id b) { return a.index == b.index && a.generation == b.generation; }
  friend bool operator!=(Id a, Id b) { return !(a == b); }
  friend bool operator<(Id a, Id b) {
    return a.index != b.index ? a.index < b.index : a.generation < b.generation;
  }
};

}  // namespace grip
