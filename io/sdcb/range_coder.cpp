#include "sdcb/io/sdcb/range_coder.h"

namespace sdcb {
namespace {

constexpr int kProbabilityBits = 11;
constexpr uint32_t kProbabilityOne = 1u << kProbabilityBits;
constexpr int kAdaptShift = 5;
constexpr uint32_t kTop = 1u << 24;

}  // namespace

int BitLength(uint32_t z) {
  int n = 0;
  while (z != 0) {
    ++n;
    z >>= 1;
  }
  return n;
}

// ---------------------------------------------------------------------------

void RangeEncoder::ShiftLow() {
  if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
    const uint8_t carry = static_cast<uint8_t>(low_ >> 32);
    uint8_t pending = cache_;
    do {
      out_ += static_cast<char>(static_cast<uint8_t>(pending + carry));
      pending = 0xFF;
    } while (--cache_size_ != 0);
    cache_ = static_cast<uint8_t>(low_ >> 24);
  }
  ++cache_size_;
  low_ = (low_ & 0x00FFFFFFu) << 8;
}

void RangeEncoder::EncodeBit(BitProbability* p, int bit) {
  const uint32_t bound = (range_ >> kProbabilityBits) * *p;
  if (bit == 0) {
    range_ = bound;
    *p = static_cast<BitProbability>(*p +
                                     ((kProbabilityOne - *p) >> kAdaptShift));
  } else {
    low_ += bound;
    range_ -= bound;
    *p = static_cast<BitProbability>(*p - (*p >> kAdaptShift));
  }
  while (range_ < kTop) {
    range_ <<= 8;
    ShiftLow();
  }
}

void RangeEncoder::EncodeDirectBits(uint32_t value, int count) {
  for (int i = count - 1; i >= 0; --i) {
    range_ >>= 1;
    if ((value >> i) & 1u) low_ += range_;
    while (range_ < kTop) {
      range_ <<= 8;
      ShiftLow();
    }
  }
}

std::string RangeEncoder::Finish() {
  for (int i = 0; i < 5; ++i) ShiftLow();
  // The first byte is always the initial cache, 0: not stored.
  return out_.substr(1);
}

// ---------------------------------------------------------------------------

RangeDecoder::RangeDecoder(std::string_view stream) : stream_(stream) {
  for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | NextByte();
}

uint8_t RangeDecoder::NextByte() {
  if (pos_ >= stream_.size()) {
    overran_ = true;
    return 0;
  }
  return static_cast<uint8_t>(stream_[pos_++]);
}

void RangeDecoder::Normalize() {
  while (range_ < kTop) {
    range_ <<= 8;
    code_ = (code_ << 8) | NextByte();
  }
}

int RangeDecoder::DecodeBit(BitProbability* p) {
  const uint32_t bound = (range_ >> kProbabilityBits) * *p;
  int bit;
  if (code_ < bound) {
    range_ = bound;
    *p = static_cast<BitProbability>(*p +
                                     ((kProbabilityOne - *p) >> kAdaptShift));
    bit = 0;
  } else {
    code_ -= bound;
    range_ -= bound;
    *p = static_cast<BitProbability>(*p - (*p >> kAdaptShift));
    bit = 1;
  }
  Normalize();
  return bit;
}

uint32_t RangeDecoder::DecodeDirectBits(int count) {
  uint32_t value = 0;
  for (int i = 0; i < count; ++i) {
    range_ >>= 1;
    uint32_t bit = 0;
    if (code_ >= range_) {
      code_ -= range_;
      bit = 1;
    }
    value = (value << 1) | bit;
    Normalize();
  }
  return value;
}

// ---------------------------------------------------------------------------

IntegerModel::IntegerModel(int contexts)
    : length_(static_cast<size_t>(contexts) * kLengthTree, kHalfProbability),
      second_(static_cast<size_t>(contexts) * kLengths, kHalfProbability) {}

void IntegerModel::Encode(uint32_t z, int context, RangeEncoder* encoder) {
  const int n = BitLength(z);
  BitProbability* tree = &length_[static_cast<size_t>(context) * kLengthTree];
  int node = 1;
  for (int level = 5; level >= 0; --level) {
    const int bit = (n >> level) & 1;
    encoder->EncodeBit(&tree[node], bit);
    node = 2 * node + bit;
  }
  if (n >= 2) {
    encoder->EncodeBit(&second_[static_cast<size_t>(context) * kLengths + n],
                       static_cast<int>((z >> (n - 2)) & 1u));
    encoder->EncodeDirectBits(z, n - 2);
  }
}

bool IntegerModel::Decode(int context, RangeDecoder* decoder, uint32_t* z) {
  BitProbability* tree = &length_[static_cast<size_t>(context) * kLengthTree];
  int node = 1;
  for (int level = 5; level >= 0; --level) {
    node = 2 * node + decoder->DecodeBit(&tree[node]);
  }
  const int n = node - kLengthTree;
  if (n > 32) return false;
  if (n < 2) {
    *z = static_cast<uint32_t>(n);
    return true;
  }
  const uint32_t second = static_cast<uint32_t>(decoder->DecodeBit(
      &second_[static_cast<size_t>(context) * kLengths + n]));
  const uint32_t top = (1u << 1 | second) << (n - 2);
  *z = top | decoder->DecodeDirectBits(n - 2);
  return true;
}

}  // namespace sdcb
