#include "sdcb/io/sdcb/crc32.h"

#include <array>

namespace sdcb {
namespace {

constexpr uint32_t kReflectedPolynomial = 0xEDB88320u;

// table[b] = CRC register after shifting the byte b through 8 steps.
constexpr std::array<uint32_t, 256> MakeTable() {
  std::array<uint32_t, 256> table{};
  for (uint32_t b = 0; b < 256; ++b) {
    uint32_t r = b;
    for (int bit = 0; bit < 8; ++bit) {
      r = (r & 1u) ? (r >> 1) ^ kReflectedPolynomial : r >> 1;
    }
    table[b] = r;
  }
  return table;
}

constexpr std::array<uint32_t, 256> kTable = MakeTable();

}  // namespace

uint32_t Crc32Update(uint32_t crc, const void* data, size_t size) {
  const auto* bytes = static_cast<const uint8_t*>(data);
  uint32_t r = ~crc;
  for (size_t i = 0; i < size; ++i) {
    r = kTable[(r ^ bytes[i]) & 0xFFu] ^ (r >> 8);
  }
  return ~r;
}

}  // namespace sdcb
