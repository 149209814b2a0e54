// libFuzzer target: the runtime asset reader (collision/asset.hpp decodeAsset + makeAssetShape).
// Each input is decoded twice: as given (exercising the header, size and checksum checks) and
// with its header's payload size and checksum made to match, so that the fuzzer reaches the
// field-by-field payload checks behind the checksum. Only grip::Error may come out.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "collision/asset.hpp"
#include "core/error.hpp"
#include "core/hash.hpp"

namespace {

void decodeAndBuild(const std::vector<uint8_t>& bytes) {
  try {
    const grip::AssetData a = grip::decodeAsset(bytes);
    grip::makeAssetShape(a);
  } catch (const grip::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  decodeAndBuild(bytes);
  // Header: magic (8), version (4), reserved (4), payload size (8), checksum (8).
  constexpr size_t kHeader = 32;
  if (bytes.size() >= kHeader) {
    const uint64_t payload = bytes.size() - kHeader;
    grip::StateHash h;
    h.add(bytes.data() + kHeader, payload);
    const uint64_t checksum = h.value();
    std::memcpy(bytes.data() + 16, &payload, 8);
    std::memcpy(bytes.data() + 24, &checksum, 8);
    decodeAndBuild(bytes);
  }
  return 0;
}
