// Byte-level packing for the `.sdcb` file (docs/FORMAT.md, "Packed
// payloads"): byte planes (the shuffle filter of HDF5 / Blosc) and zlib
// streams whose inflated size is fixed before inflating.
//
// Why byte planes: the bytes of an array of doubles repeat by position (the
// sign/exponent bytes of nearby values agree, the low mantissa bytes are
// noise); grouping byte b of every value together gives deflate long runs
// to work with. On bunny00's 3640 control points deflate alone saves 4 %,
// byte planes first 15 % (bench/decimation_tables.sh sizes).
#ifndef SDCB_IO_SDCB_BYTE_PACKING_H_
#define SDCB_IO_SDCB_BYTE_PACKING_H_

#include <cstdint>
#include <string>
#include <string_view>

#include "sdcb/core/common/status.h"

namespace sdcb {

// `values`: a sequence of values of `width` bytes each (values.size() a
// multiple of width). Returns plane 0 (byte 0 of every value, in order),
// then plane 1, ..., plane width - 1: out[b * n + i] = values[i * width + b].
std::string ToBytePlanes(std::string_view values, int width);
// The inverse of ToBytePlanes.
std::string FromBytePlanes(std::string_view planes, int width);

// Deflate cannot expand data by more than this factor (zlib's documented
// limit, 1032:1), so an inflated size above kMaxDeflateRatio * (stream
// bytes) is impossible and rejected before anything is allocated.
constexpr uint64_t kMaxDeflateRatio = 1032;

// `data` as one zlib stream (RFC 1950: deflate, compression level 6, 32 KiB
// window, Adler-32 trailer). The bytes are a function of `data` and of the
// zlib build (Debian 12: zlib 1.2.13).
std::string ZlibCompress(std::string_view data);

// Inflates the zlib stream `stream`, which must produce exactly
// `inflated_bytes` bytes, end (with a valid Adler-32) exactly at the end of
// `stream`, and satisfy inflated_bytes <= kMaxDeflateRatio * stream.size().
// Never produces more than `inflated_bytes`; the output buffer grows with
// the bytes actually produced (at most doubling), so a small stream that
// declares a large size allocates little before it fails. Any violation
// gives kCorruptFile with a message naming it (the caller adds the chunk).
StatusOr<std::string> ZlibDecompress(std::string_view stream,
                                     uint64_t inflated_bytes);

}  // namespace sdcb

#endif  // SDCB_IO_SDCB_BYTE_PACKING_H_
