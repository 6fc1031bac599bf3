// The native `.sdcb` model file: a magic number, a format version, then
// chunks (4-byte type, u64 payload length, payload, CRC-32), so the format
// can grow: readers skip chunk types they do not know. The byte layout,
// versioning rules and limits are specified in docs/FORMAT.md.
//
// Writing is deterministic (same model, same bytes: fixed chunk order, no
// timestamps, doubles stored as their exact little-endian IEEE-754 bits) and
// atomic (a temporary file renamed into place). Reading checks every length
// against the bytes present before allocating, every CRC, every index and
// every number, and returns kCorruptFile naming the problem instead of
// crashing or returning a partial model.
#ifndef SDCB_IO_SDCB_FILE_H_
#define SDCB_IO_SDCB_FILE_H_

#include <cstdint>
#include <string>
#include <string_view>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// The version this code writes and the newest it reads.
constexpr uint32_t kSdcbFormatVersion = 1;

// The 8 bytes every .sdcb file starts with: 0x89 "SDCB" CR LF 0x1A. The
// non-ASCII first byte and the CR LF pair detect 7-bit and text-mode
// (newline-converting) transfers, 0x1A stops `type` on DOS.
inline constexpr char kSdcbMagic[8] = {'\x89', 'S',    'D',    'C',
                                       'B',    '\x0D', '\x0A', '\x1A'};

// The complete file contents for `model`. Fails with kInvalidArgument if
// ValidateSplineModel(model) fails (an invalid model is never written).
StatusOr<std::string> SerializeSdcb(const SplineModel& model);

// Parses complete file contents. Any malformation (bad magic, newer version,
// truncation, bad CRC, missing or duplicate required chunk, sizes that do not
// match the declared counts, an index out of range, a non-finite number, a
// model that fails ValidateSplineModel) gives kCorruptFile (kUnsupported for a
// newer format version) with a message naming the problem; the caller adds
// the file name.
StatusOr<SplineModel> ParseSdcb(std::string_view bytes);

// SerializeSdcb(model) written to `path` atomically: on failure `path` is
// left untouched. Messages start with `path`.
Status WriteSdcbFile(const SplineModel& model, const std::string& path);

// Reads and parses `path`. kIoError if it cannot be read; otherwise as
// ParseSdcb. Messages start with `path`.
StatusOr<SplineModel> ReadSdcbFile(const std::string& path);

}  // namespace sdcb

#endif  // SDCB_IO_SDCB_FILE_H_
