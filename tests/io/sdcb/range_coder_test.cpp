// Tests io/sdcb/range_coder.*: round trips of bits, direct bits and integers on
// random and adversarial sequences (extreme probabilities that force long
// carry chains, every bit length, the extremes of uint32), the stream's
// length against the ideal adaptive code length computed here from the
// documented probability rule, and decoders fed garbage or cut streams.
#include "sdcb/io/sdcb/range_coder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace sdcb {
namespace {

struct Step {
  int kind;  // 0: adapted bit in model `model`, 1: direct bits
  int model;
  uint32_t value;
  int count;
};

// Encodes `steps`, decodes them back and checks every value and that the
// decoder read exactly the stream.
void RoundTrip(const std::vector<Step>& steps, int models) {
  std::vector<BitProbability> enc(models, kHalfProbability);
  RangeEncoder encoder;
  for (const Step& s : steps) {
    if (s.kind == 0) {
      encoder.EncodeBit(&enc[s.model], static_cast<int>(s.value));
    } else {
      encoder.EncodeDirectBits(s.value, s.count);
    }
  }
  const std::string stream = encoder.Finish();
  std::vector<BitProbability> dec(models, kHalfProbability);
  RangeDecoder decoder(stream);
  for (size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    const uint32_t mask =
        s.count == 32 ? 0xFFFFFFFFu : (uint32_t{1} << s.count) - 1;
    const uint32_t got =
        s.kind == 0 ? static_cast<uint32_t>(decoder.DecodeBit(&dec[s.model]))
                    : decoder.DecodeDirectBits(s.count);
    ASSERT_EQ(got, s.kind == 0 ? s.value : (s.value & mask)) << "step " << i;
  }
  EXPECT_FALSE(decoder.overran());
  EXPECT_EQ(decoder.unread(), 0u);
}

TEST(RangeCoderTest, RandomBitsAndDirectBitsRoundTrip) {
  for (unsigned seed = 0; seed < 40; ++seed) {
    std::mt19937 rng(seed);
    std::vector<Step> steps;
    const int n = 1 + static_cast<int>(rng() % 5000);
    // Each model has its own bias, from almost always 0 to almost always 1.
    std::vector<double> bias(8);
    for (double& b : bias) b = std::uniform_real_distribution<>(0, 1)(rng);
    bias[0] = 0.0005;
    bias[1] = 0.9995;
    for (int i = 0; i < n; ++i) {
      if (rng() % 4 == 0) {
        const int count = static_cast<int>(rng() % 33);
        steps.push_back({1, 0, static_cast<uint32_t>(rng()), count});
      } else {
        const int model = static_cast<int>(rng() % 8);
        const uint32_t bit =
            std::uniform_real_distribution<>(0, 1)(rng) < bias[model] ? 1 : 0;
        steps.push_back({0, model, bit, 1});
      }
    }
    RoundTrip(steps, 8);
  }
}

TEST(RangeCoderTest, ExtremeSequencesRoundTrip) {
  // Long runs of the likely and of the unlikely symbol (carries ripple
  // through runs of 0xFF bytes), all-ones direct bits, and nothing at all.
  for (uint32_t bit : {0u, 1u}) {
    std::vector<Step> steps(200000, Step{0, 0, bit, 1});
    RoundTrip(steps, 1);
    for (int i = 0; i < 200000; i += 997) steps[i].value = 1 - bit;
    RoundTrip(steps, 1);
  }
  RoundTrip(std::vector<Step>(3000, Step{1, 0, 0xFFFFFFFFu, 32}), 1);
  RoundTrip(std::vector<Step>(3000, Step{1, 0, 0, 32}), 1);
  RoundTrip({}, 1);
}

// The ideal length of an adaptive code: sum of -log2 P(bit) under the
// documented rule (P(0) = p / 2048; after a 0, p += (2048 - p) >> 5, after
// a 1, p -= p >> 5), independent of the coder's arithmetic.
TEST(RangeCoderTest, LengthIsNearTheIdealAdaptiveCodeLength) {
  std::mt19937 rng(7);
  for (double bias : {0.01, 0.1, 0.3, 0.5}) {
    int p = 1024;
    double ideal_bits = 0;
    BitProbability model = kHalfProbability;
    RangeEncoder encoder;
    for (int i = 0; i < 100000; ++i) {
      const int bit = std::uniform_real_distribution<>(0, 1)(rng) < bias;
      ideal_bits += -std::log2(bit == 0 ? p / 2048.0 : 1 - p / 2048.0);
      p = bit == 0 ? p + ((2048 - p) >> 5) : p - (p >> 5);
      encoder.EncodeBit(&model, bit);
    }
    const double bytes = static_cast<double>(encoder.Finish().size());
    EXPECT_NEAR(bytes, ideal_bits / 8, 0.002 * ideal_bits / 8 + 8) << bias;
  }
  RangeEncoder direct;
  for (int i = 0; i < 1000; ++i) direct.EncodeDirectBits(rng(), 32);
  EXPECT_NEAR(static_cast<double>(direct.Finish().size()), 4000, 5);
}

TEST(RangeCoderTest, IntegersOfEveryLengthRoundTrip) {
  std::mt19937 rng(3);
  std::vector<uint32_t> values = {
      0, 1, 2, 3, 4, 0x7FFFFFFFu, 0x80000000u, 0xFFFFFFFFu, 0xFFFFFFFEu};
  for (int n = 0; n <= 32; ++n) {
    for (int k = 0; k < 50; ++k) {
      const uint32_t top = n == 0 ? 0 : uint32_t{1} << (n - 1);
      const uint32_t low =
          n <= 1 ? 0 : static_cast<uint32_t>(rng()) & (top - 1);
      values.push_back(top | low);
    }
  }
  std::vector<int> contexts;
  for (size_t i = 0; i < values.size(); ++i) {
    contexts.push_back(static_cast<int>(rng() % 5));
    EXPECT_EQ(BitLength(values[i]),
              values[i] == 0 ? 0 : 32 - __builtin_clz(values[i]));
  }
  IntegerModel enc_model(5);
  RangeEncoder encoder;
  for (size_t i = 0; i < values.size(); ++i) {
    enc_model.Encode(values[i], contexts[i], &encoder);
  }
  const std::string stream = encoder.Finish();
  IntegerModel dec_model(5);
  RangeDecoder decoder(stream);
  for (size_t i = 0; i < values.size(); ++i) {
    uint32_t z = 0;
    ASSERT_TRUE(dec_model.Decode(contexts[i], &decoder, &z));
    ASSERT_EQ(z, values[i]) << i;
  }
  EXPECT_EQ(decoder.unread(), 0u);
  EXPECT_FALSE(decoder.overran());
}

TEST(RangeCoderTest, ZigzagIsItsInverseAndSmallForSmallDifferences) {
  for (int64_t d : {0LL, 1LL, -1LL, 2LL, -2LL, 2147483647LL, -2147483648LL}) {
    const uint32_t diff = static_cast<uint32_t>(static_cast<int32_t>(d));
    EXPECT_EQ(Unzigzag(Zigzag(diff)), diff);
    EXPECT_EQ(Zigzag(diff), d >= 0 ? static_cast<uint32_t>(2 * d)
                                   : static_cast<uint32_t>(-2 * d - 1));
  }
}

TEST(RangeCoderTest, GarbageAndCutStreamsNeverReadPastTheirEnd) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    std::string garbage(rng() % 64, '\0');
    for (char& c : garbage) c = static_cast<char>(rng());
    IntegerModel model(3);
    RangeDecoder decoder(garbage);
    int rejected = 0;
    for (int i = 0; i < 1000; ++i) {
      uint32_t z;
      if (!model.Decode(i % 3, &decoder, &z)) ++rejected;
    }
    // 1000 values cannot come from at most 63 bytes without running out.
    EXPECT_TRUE(decoder.overran() || rejected > 0);
    EXPECT_LE(decoder.unread(), garbage.size());
  }
  // A valid stream cut short is detected.
  IntegerModel enc_model(1);
  RangeEncoder encoder;
  for (int i = 0; i < 500; ++i) enc_model.Encode(rng(), 0, &encoder);
  const std::string stream = encoder.Finish();
  for (size_t cut = 0; cut < stream.size(); cut += 7) {
    IntegerModel dec_model(1);
    RangeDecoder decoder(std::string_view(stream).substr(0, cut));
    uint32_t z;
    for (int i = 0; i < 500; ++i) (void)dec_model.Decode(0, &decoder, &z);
    EXPECT_TRUE(decoder.overran()) << cut;
  }
}

}  // namespace
}  // namespace sdcb
