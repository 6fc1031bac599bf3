// Tests io/sdcb/byte_packing.*: byte planes against their definition, zlib
// streams against zlib's own one-shot uncompress/compress2, and the bounded
// inflater on streams that lie about their size.
#include "sdcb/io/sdcb/byte_packing.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <random>
#include <string>

#include "testing/allocation_tracker.h"

namespace sdcb {
namespace {

std::string RandomBytes(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (char& c : s) c = static_cast<char>(rng());
  return s;
}

std::string ZlibReference(const std::string& data) {
  uLongf size = compressBound(static_cast<uLong>(data.size()));
  std::string out(size, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &size,
                      reinterpret_cast<const Bytef*>(data.data()),
                      static_cast<uLong>(data.size()), 6),
            Z_OK);
  out.resize(size);
  return out;
}

TEST(BytePackingTest, BytePlanesFollowTheirDefinition) {
  const std::string values = "ABCDabcd0123";  // three 4-byte values
  EXPECT_EQ(ToBytePlanes(values, 4), "Aa0Bb1Cc2Dd3");
  EXPECT_EQ(FromBytePlanes("Aa0Bb1Cc2Dd3", 4), values);
  for (int width : {1, 4, 8}) {
    const std::string s = RandomBytes(8 * 1000, width);
    EXPECT_EQ(FromBytePlanes(ToBytePlanes(s, width), width), s);
  }
  EXPECT_EQ(ToBytePlanes("", 8), "");
}

TEST(BytePackingTest, StreamsAreStandardZlib) {
  for (size_t n : {size_t{0}, size_t{1}, size_t{1000}, size_t{300000}}) {
    // Half random, half repetitive.
    const std::string data =
        RandomBytes(n / 2, 5) + std::string(n - n / 2, 'x');
    const std::string stream = ZlibCompress(data);
    // zlib's own inflater reads it...
    std::string back(n, '\0');
    uLongf size = static_cast<uLongf>(n);
    ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(back.data()), &size,
                         reinterpret_cast<const Bytef*>(stream.data()),
                         static_cast<uLong>(stream.size())),
              Z_OK);
    EXPECT_EQ(back, data);
    // ... and ours reads zlib's.
    const StatusOr<std::string> ours = ZlibDecompress(ZlibReference(data), n);
    ASSERT_TRUE(ours.ok()) << ours.status().message();
    EXPECT_EQ(*ours, data);
    EXPECT_EQ(ZlibCompress(data), stream);  // deterministic
  }
}

TEST(BytePackingTest, InflaterHoldsTheDeclaredSize) {
  // 20 KB of noise and 1 MiB of 'a': ~21 KB of stream.
  const std::string data = RandomBytes(20000, 3) + std::string(1 << 20, 'a');
  const std::string stream = ZlibCompress(data);
  ASSERT_LT(stream.size(), 22000u);
  // Declared smaller: stops there, without allocating the real size.
  StatusOr<std::string> r = InternalError("");
  const size_t largest = testing::LargestAllocationDuring(
      [&] { r = ZlibDecompress(stream, 5000); });
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kCorruptFile);
  EXPECT_NE(r.status().message().find("more than its 5000 declared"),
            std::string::npos);
  EXPECT_LT(largest, 64 * 1024);
  // Declared larger: the stream ends first; the buffer grew only with the
  // output.
  const size_t larger = testing::LargestAllocationDuring(
      [&] { r = ZlibDecompress(stream, 2 * data.size()); });
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("inflates to 1068576 bytes, not its"),
            std::string::npos)
      << r.status().message();
  // Cut: ends early.
  r = ZlibDecompress(stream.substr(0, stream.size() / 2), data.size());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("ends early"), std::string::npos)
      << r.status().message();
  EXPECT_LE(larger, 2 * data.size() + 64 * 1024);
  // Beyond deflate's 1032:1: refused up front.
  r = ZlibDecompress(stream, kMaxDeflateRatio * stream.size() + 1);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("more than deflate allows"),
            std::string::npos);
  // Exact: fine.
  r = ZlibDecompress(stream, data.size());
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(*r, data);
  // Empty input.
  EXPECT_FALSE(ZlibDecompress("", 0).ok());
  EXPECT_TRUE(ZlibDecompress(ZlibCompress(""), 0).ok());
}

}  // namespace
}  // namespace sdcb
