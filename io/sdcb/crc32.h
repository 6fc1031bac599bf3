// CRC-32 as used by zlib, PNG and Ethernet (IEEE 802.3): reflected
// polynomial 0xEDB88320, initial value and final XOR 0xFFFFFFFF. Check value:
// Crc32("123456789") == 0xCBF43926.
#ifndef SDCB_IO_SDCB_CRC32_H_
#define SDCB_IO_SDCB_CRC32_H_

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace sdcb {

// Continues a CRC over `size` more bytes at `data`: Crc32Update(0, a) then
// Crc32Update(that, b) equals the CRC of the concatenation a + b. Start with
// crc = 0.
uint32_t Crc32Update(uint32_t crc, const void* data, size_t size);

inline uint32_t Crc32(std::string_view bytes) {
  return Crc32Update(0, bytes.data(), bytes.size());
}

}  // namespace sdcb

#endif  // SDCB_IO_SDCB_CRC32_H_
