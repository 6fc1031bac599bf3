#include "sdcb/io/sdcb/byte_packing.h"

#include <zlib.h>

#include <algorithm>
#include <cassert>
#include <limits>
#include <new>

namespace sdcb {
namespace {

std::string Str(uint64_t x) { return std::to_string(x); }

// zlib counts in uInt (32 bits); feed it at most this much per call.
constexpr uint64_t kMaxStep = std::numeric_limits<uInt>::max();

// Smallest buffer the inflater starts with (then doubles, capped).
constexpr uint64_t kInitialOutput = 1024;

}  // namespace

std::string ToBytePlanes(std::string_view values, int width) {
  assert(width > 0 && values.size() % width == 0);
  const size_t n = values.size() / width;
  std::string out(values.size(), '\0');
  for (size_t i = 0; i < n; ++i) {
    for (int b = 0; b < width; ++b) out[b * n + i] = values[i * width + b];
  }
  return out;
}

std::string FromBytePlanes(std::string_view planes, int width) {
  assert(width > 0 && planes.size() % width == 0);
  const size_t n = planes.size() / width;
  std::string out(planes.size(), '\0');
  for (size_t i = 0; i < n; ++i) {
    for (int b = 0; b < width; ++b) out[i * width + b] = planes[b * n + i];
  }
  return out;
}

std::string ZlibCompress(std::string_view data) {
  z_stream z{};
  // Level 6 (zlib's default), default window (15 bits), memory level (8)
  // and strategy. Level 9 gains 0.2 % on packed doubles and takes 13x as
  // long (2.2 s instead of 0.17 s for 2 MB of them).
  if (deflateInit(&z, 6) != Z_OK) throw std::bad_alloc();
  std::string out(deflateBound(&z, data.size()), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  size_t in_left = data.size(), out_left = out.size();
  int result = Z_OK;
  while (result != Z_STREAM_END) {
    const auto in_step =
        static_cast<uInt>(std::min<uint64_t>(in_left, kMaxStep));
    const auto out_step =
        static_cast<uInt>(std::min<uint64_t>(out_left, kMaxStep));
    z.avail_in = in_step;
    z.avail_out = out_step;
    result = deflate(&z, in_step == in_left ? Z_FINISH : Z_NO_FLUSH);
    // deflateBound guarantees room, so only Z_OK / Z_STREAM_END occur.
    assert(result == Z_OK || result == Z_STREAM_END);
    in_left -= in_step - z.avail_in;
    out_left -= out_step - z.avail_out;
  }
  out.resize(out.size() - out_left);
  deflateEnd(&z);
  return out;
}

StatusOr<std::string> ZlibDecompress(std::string_view stream,
                                     uint64_t inflated_bytes) {
  // (stream.size() < 2^54 for anything held in memory: no overflow.)
  if (inflated_bytes > kMaxDeflateRatio * uint64_t{stream.size()}) {
    return CorruptFileError("a zlib stream of " + Str(stream.size()) +
                            " bytes declares " + Str(inflated_bytes) +
                            " inflated bytes, more than deflate allows");
  }
  z_stream z{};
  if (inflateInit(&z) != Z_OK) throw std::bad_alloc();
  std::string out;
  out.resize(std::min(inflated_bytes,
                      std::max(kInitialOutput, 4 * uint64_t{stream.size()})));
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(stream.data()));
  size_t in_left = stream.size();
  uint64_t produced = 0;
  int result = Z_OK;
  while (true) {
    if (produced == out.size()) {
      if (out.size() == inflated_bytes) {
        // Everything declared has been produced: the stream must end here
        // (inflate reports Z_STREAM_END, with no output room, only if the
        // trailer follows; probe with a one-byte window).
        char extra = 0;
        const auto in_step =
            static_cast<uInt>(std::min<uint64_t>(in_left, kMaxStep));
        z.avail_in = in_step;
        z.next_out = reinterpret_cast<Bytef*>(&extra);
        z.avail_out = 1;
        result = inflate(&z, Z_FINISH);
        in_left -= in_step - z.avail_in;
        if (z.avail_out == 0) {
          inflateEnd(&z);
          return CorruptFileError("a zlib stream inflates to more than its " +
                                  Str(inflated_bytes) + " declared bytes");
        }
        break;
      }
      out.resize(std::min(inflated_bytes, 2 * out.size()));
    }
    const auto in_step =
        static_cast<uInt>(std::min<uint64_t>(in_left, kMaxStep));
    const auto out_step =
        static_cast<uInt>(std::min<uint64_t>(out.size() - produced, kMaxStep));
    z.avail_in = in_step;
    z.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
    z.avail_out = out_step;
    result = inflate(&z, Z_NO_FLUSH);
    in_left -= in_step - z.avail_in;
    produced += out_step - z.avail_out;
    // Z_STREAM_END: done; Z_BUF_ERROR: no progress (the input ran out);
    // anything else: an error.
    if (result != Z_OK) break;
  }
  const std::string zlib_message = z.msg != nullptr ? z.msg : "invalid data";
  inflateEnd(&z);
  if (result == Z_DATA_ERROR || result == Z_NEED_DICT ||
      result == Z_STREAM_ERROR) {
    return CorruptFileError("a zlib stream is corrupt (" + zlib_message + ")");
  }
  if (result == Z_MEM_ERROR) throw std::bad_alloc();
  if (result != Z_STREAM_END) {
    return CorruptFileError("a zlib stream ends early, after " + Str(produced) +
                            " of its " + Str(inflated_bytes) +
                            " declared bytes");
  }
  if (produced != inflated_bytes) {
    return CorruptFileError("a zlib stream inflates to " + Str(produced) +
                            " bytes, not its " + Str(inflated_bytes) +
                            " declared bytes");
  }
  if (in_left != 0) {
    return CorruptFileError(Str(in_left) +
                            " bytes follow the end of a zlib "
                            "stream");
  }
  return out;
}

}  // namespace sdcb
