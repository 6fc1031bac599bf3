// An adaptive binary range coder (the carry-propagating coder of LZMA, with
// 11-bit probabilities adapted by 1/32 of the error per bit) and the integer
// code built on it that the `.sdcb` PCTL and QKNT chunks use
// (docs/FORMAT.md, "Chunks of versions 2 and 3"). Written here; the byte stream
// is specified in docs/FORMAT.md so that other readers can be written.
//
// The decoder never reads past its input and never allocates: a stream that
// ends early decodes as if zero bytes followed and sets overran(), which
// callers treat as corrupt, so hostile input costs at most the work of the
// values the caller asks for.
#ifndef SDCB_IO_SDCB_RANGE_CODER_H_
#define SDCB_IO_SDCB_RANGE_CODER_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace sdcb {

// Probability (of a 0 bit) in units of 2^-11; starts at one half.
using BitProbability = uint16_t;
constexpr BitProbability kHalfProbability = 1024;

class RangeEncoder {
 public:
  void EncodeBit(BitProbability* p, int bit);
  // `count` (0..32) low bits of `value`, most significant first, each with
  // probability one half (not adapted).
  void EncodeDirectBits(uint32_t value, int count);
  // Flushes and returns the stream; the encoder is then spent.
  std::string Finish();

 private:
  void ShiftLow();
  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t cache_size_ = 1;
  std::string out_;
};

class RangeDecoder {
 public:
  explicit RangeDecoder(std::string_view stream);
  int DecodeBit(BitProbability* p);
  uint32_t DecodeDirectBits(int count);
  // Whether the decoder needed bytes beyond the stream.
  bool overran() const { return overran_; }
  // Bytes of the stream not read (a valid stream from RangeEncoder::Finish
  // leaves none once every value was decoded).
  size_t unread() const { return stream_.size() - pos_; }

 private:
  uint8_t NextByte();
  void Normalize();
  std::string_view stream_;
  size_t pos_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint32_t code_ = 0;
  bool overran_ = false;
};

// Adaptive models of unsigned 32-bit integers (zigzag-coded residuals) in a
// few contexts. A value z is coded as its bit length n (0..32; z = 0 has
// length 0) by a 6-level binary tree of adapted probabilities, then, for
// n >= 2, the bit below the leading one with an adapted probability of its
// own (per context and n), then the n - 2 bits below it direct.
class IntegerModel {
 public:
  explicit IntegerModel(int contexts);
  void Encode(uint32_t z, int context, RangeEncoder* encoder);
  // False (and *z unset) for a bit length above 32, which no encoder writes.
  bool Decode(int context, RangeDecoder* decoder, uint32_t* z);

 private:
  static constexpr int kLengthTree = 64;  // 6 levels
  static constexpr int kLengths = 33;
  std::vector<BitProbability> length_;  // contexts x kLengthTree
  std::vector<BitProbability> second_;  // contexts x kLengths
};

// The bit length of z: 0 for 0, else floor(log2 z) + 1.
int BitLength(uint32_t z);

// Zigzag code of a 32-bit difference taken modulo 2^32 and read as int32:
// small differences of either sign give small codes.
inline uint32_t Zigzag(uint32_t difference) {
  return (difference << 1) ^ (0u - (difference >> 31));
}
inline uint32_t Unzigzag(uint32_t z) { return (z >> 1) ^ (0u - (z & 1u)); }

}  // namespace sdcb

#endif  // SDCB_IO_SDCB_RANGE_CODER_H_
