// Tests format version 3's chunks (docs/FORMAT.md): QKNT (knots on the
// octahedral grid, unpacked here bit by bit from the document's layout) and
// PCTL (predicted, range-coded control points, which must decode to exactly
// the quantizer's values), the version the writer chooses, and hostile
// input: every single-byte corruption and truncation, structure-aware
// mutations with valid CRCs, crafted chunks.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "sdcb/core/sphere/unit_vector_grid.h"
#include "sdcb/io/sdcb/control_point_quantization.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/allocation_tracker.h"
#include "testing/sdcb_test_codec.h"
#include "testing/spline_model_fixture.h"

namespace sdcb {
namespace {

using testing::ExpectCorrupt;
using testing::Find;
using testing::GetLe;
using testing::Le;
using testing::RawChunk;
using testing::SplitFile;

std::string Join(const std::vector<RawChunk>& chunks, uint32_t version = 3) {
  return testing::JoinFile(chunks, version);
}

SplineModel GridModel(int degree, int knots, int bits, unsigned seed = 7) {
  return testing::MakeGridTestModel(degree, knots, bits, seed);
}

std::string Serialize(const SplineModel& m, int quantize_bits,
                      SdcbFileInfo* info = nullptr) {
  SdcbWriteOptions o;
  o.quantize_bits = quantize_bits;
  StatusOr<std::string> bytes = SerializeSdcb(m, o, info);
  EXPECT_TRUE(bytes.ok()) << bytes.status().message();
  return bytes.ok() ? *bytes : std::string();
}

uint32_t VersionOf(const std::string& file) {
  return static_cast<uint32_t>(GetLe(file, 8, 4));
}

TEST(SdcbFileV3Test, GridKnotsAreStoredAsTheirCodes) {
  // (Coarser grids would make random knots meet.)
  for (int bits : {5, 7, 16, 26}) {
    const SplineModel model = GridModel(2, 12, bits);
    SdcbFileInfo info;
    const std::string file = Serialize(model, 0, &info);
    EXPECT_EQ(VersionOf(file), 3u);
    EXPECT_EQ(info.knot_grid_bits, bits);
    std::vector<RawChunk> chunks = SplitFile(file);
    ASSERT_EQ(Find(chunks, "KNOT"), nullptr);
    ASSERT_NE(Find(chunks, "CTRL"), nullptr);
    const std::string& q = Find(chunks, "QKNT")->payload;
    ASSERT_EQ(q.size(), 4 + (2 * bits * 12 + 7) / 8);
    EXPECT_EQ(GetLe(q, 0, 4), static_cast<uint64_t>(bits));
    // Unpacked bit by bit, most significant first: a, b of each knot.
    auto bit = [&](size_t i) {
      return (static_cast<uint8_t>(q[4 + i / 8]) >> (7 - i % 8)) & 1u;
    };
    size_t at = 0;
    for (int k = 0; k < 12; ++k) {
      UnitVectorCode code;
      for (uint32_t* v : {&code.a, &code.b}) {
        for (int j = 0; j < bits; ++j) *v = (*v << 1) | bit(at++);
      }
      EXPECT_TRUE(
          testing::SameBits(DecodeUnitVector(code, bits).transpose().eval(),
                            model.knots.row(k).eval()))
          << k << " bits " << bits;
    }
    for (; at < 8 * (q.size() - 4); ++at) EXPECT_EQ(bit(at), 0u);
    const StatusOr<SplineModel> back = ParseSdcb(file);
    ASSERT_TRUE(back.ok()) << back.status().message();
    EXPECT_TRUE(testing::BitIdentical(model, *back));
  }
}

TEST(SdcbFileV3Test, TheWriterUsesTheLowestVersionThatHoldsTheFile) {
  SplineModel model = GridModel(2, 12, 16);
  // Version 2 on request: KNOT and QCTL.
  SdcbWriteOptions o;
  o.quantize_bits = 12;
  o.format_version = 2;
  std::string file = *SerializeSdcb(model, o);
  EXPECT_EQ(VersionOf(file), 2u);
  std::vector<RawChunk> version2_chunks = SplitFile(file);
  EXPECT_NE(Find(version2_chunks, "QCTL"), nullptr);
  // Knots off the grid they claim, and no quantization: version 2.
  model.statistics.options.knot_grid_bits = 17;
  file = Serialize(model, 0);
  EXPECT_EQ(VersionOf(file), 2u);
  std::vector<RawChunk> chunks = SplitFile(file);
  EXPECT_NE(Find(chunks, "KNOT"), nullptr);
  // Quantized: PCTL, version 3, also with KNOT.
  file = Serialize(model, 12);
  EXPECT_EQ(VersionOf(file), 3u);
  chunks = SplitFile(file);
  EXPECT_NE(Find(chunks, "KNOT"), nullptr);
  EXPECT_NE(Find(chunks, "PCTL"), nullptr);
  EXPECT_EQ(Find(chunks, "QCTL"), nullptr);
  o.format_version = 4;
  EXPECT_EQ(SerializeSdcb(model, o).status().code(),
            StatusCode::kInvalidArgument);
}

TEST(SdcbFileV3Test, PredictedControlPointsDecodeToTheQuantizersValues) {
  for (int degree : {0, 2, 4}) {
    const SplineModel model = GridModel(degree, 14, 16, 3 + degree);
    for (int bits : {1, 5, 12, 20, 32}) {
      SdcbFileInfo info;
      const std::string file = Serialize(model, bits, &info);
      const StatusOr<SplineModel> back = ParseSdcb(file);
      ASSERT_TRUE(back.ok()) << back.status().message();
      const StatusOr<QuantizedControlPoints> q =
          QuantizeControlPoints(model, bits);
      ASSERT_TRUE(q.ok());
      EXPECT_TRUE(testing::SameBits(back->control_points, q->values))
          << degree << " " << bits;
      EXPECT_EQ(info.quantization.max_displacement,
                q->quantization.max_displacement);
      SdcbFileInfo read_info;
      ASSERT_TRUE(ParseSdcb(file, &read_info).ok());
      EXPECT_EQ(read_info.quantization.bits, bits);
      EXPECT_EQ(read_info.knot_grid_bits, 16);
    }
  }
}

TEST(SdcbFileV3Test, AutoQuantizationTakesTheCoarsestGridWithinTheBudget) {
  const SplineModel model = GridModel(2, 14, 16);
  const double rms = model.statistics.final_result.rmse_percent / 100;
  for (double fraction : {0.001, 0.01, 0.1, 1.0}) {
    SdcbWriteOptions o;
    o.quantize_bits = kQuantizeBitsAuto;
    o.quantize_fraction_of_rms = fraction;
    SdcbFileInfo info;
    const StatusOr<std::string> file = SerializeSdcb(model, o, &info);
    ASSERT_TRUE(file.ok());
    const ControlPointQuantization& q = info.quantization;
    const double budget = fraction * rms;
    EXPECT_LE(q.surface_error_bound(), budget);
    // Cubic cells of the largest step the bound allows, and the fewest bits
    // that hold the codes.
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(q.step[c], 2 * budget / std::sqrt(3.0), 1e-12 * budget);
    }
    const double largest = (model.control_points.colwise().maxCoeff() -
                            model.control_points.colwise().minCoeff())
                               .maxCoeff() /
                           q.step[0];
    EXPECT_LE(std::round(largest), std::ldexp(1.0, q.bits) - 1);
    EXPECT_GT(std::round(largest), std::ldexp(1.0, q.bits - 1) - 1);
    // What the file stores: every point within the bound, read back.
    const StatusOr<SplineModel> back = ParseSdcb(*file);
    ASSERT_TRUE(back.ok());
    EXPECT_LE((back->control_points - model.control_points)
                  .rowwise()
                  .norm()
                  .maxCoeff(),
              budget);
  }
  SplineModel no_rms = model;
  no_rms.statistics.final_result.rmse_percent = 0;
  SdcbWriteOptions o;
  o.quantize_bits = kQuantizeBitsAuto;
  EXPECT_EQ(SerializeSdcb(no_rms, o).status().code(),
            StatusCode::kInvalidArgument);
}

TEST(SdcbFileV3Test, EverySingleByteCorruptionAndTruncationIsRejected) {
  const SplineModel model = GridModel(1, 8, 16);
  const std::string file = Serialize(model, 12);
  ASSERT_LT(file.size(), 4000u);
  const StatusOr<SplineModel> reference = ParseSdcb(file);
  ASSERT_TRUE(reference.ok());
  const size_t largest =
      testing::ExpectEverySingleByteCorruptionRejected(file, *reference);
  EXPECT_LT(largest, 16 * file.size() + 4096);
  for (size_t length = 0; length < file.size(); ++length) {
    EXPECT_FALSE(ParseSdcb(file.substr(0, length)).ok()) << length;
  }
}

TEST(SdcbFileV3Test, RandomMutationsWithValidCrcsAreRejectedOrFaithful) {
  const std::vector<RawChunk> good =
      SplitFile(Serialize(GridModel(1, 8, 16), 12));
  const size_t good_size = Join(good).size();
  std::mt19937 rng(5);
  int accepted = 0;
  size_t largest_overall = 0;
  constexpr int kIterations = 6000;
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    std::vector<RawChunk> chunks = good;
    RawChunk& chunk = *Find(chunks, iteration % 2 == 0 ? "QKNT" : "PCTL");
    testing::MutateBytes(&rng, &chunk.payload);
    StatusOr<SplineModel> m = InternalError("not parsed");
    const std::string bytes = Join(chunks);
    largest_overall = std::max(
        largest_overall,
        testing::LargestAllocationDuring([&] { m = ParseSdcb(bytes); }));
    if (!m.ok()) {
      EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile);
      EXPECT_FALSE(m.status().message().empty());
      continue;
    }
    ++accepted;
    testing::ExpectWritesBackFaithfully(*m);
  }
  EXPECT_LT(largest_overall, 16 * good_size + 64 * 1024);
  EXPECT_LT(accepted, kIterations - 100);
}

TEST(SdcbFileV3Test, CraftedChunksAreRejectedWithTheirReason) {
  const std::string file = Serialize(GridModel(1, 8, 16), 12);
  const auto edit = [&](const char* type, auto change) {
    std::vector<RawChunk> chunks = SplitFile(file);
    change(&Find(chunks, type)->payload);
    return Join(chunks);
  };
  ExpectCorrupt(
      edit("QKNT", [](std::string* p) { p->replace(0, 4, Le(1, 4)); }),
      "needs a grid of 2..26 bits");
  ExpectCorrupt(
      edit("QKNT", [](std::string* p) { p->replace(0, 4, Le(27, 4)); }),
      "needs a grid of 2..26 bits");
  ExpectCorrupt(edit("QKNT", [](std::string* p) { p->push_back('\0'); }),
                "bytes of codes");
  ExpectCorrupt(edit("QKNT", [](std::string* p) { p->resize(2); }),
                "needs a grid");
  ExpectCorrupt(edit("PCTL", [](std::string* p) { p->push_back('\0'); }),
                "after its last control point");
  ExpectCorrupt(edit("PCTL", [](std::string* p) { p->resize(p->size() - 2); }),
                "the PCTL chunk");
  ExpectCorrupt(edit("PCTL", [](std::string* p) { p->resize(60); }),
                "the PCTL chunk has 60 bytes");
  ExpectCorrupt(
      edit("PCTL", [](std::string* p) { p->replace(0, 4, Le(33, 4)); }),
      "declares 33 bits");
  std::vector<RawChunk> chunks = SplitFile(file);
  // The same chunks labelled version 2: QKNT and PCTL mean nothing there.
  ExpectCorrupt(Join(chunks, 2), "the required chunk 'KNOT' is missing");
  // A version 3 file without version 3's chunks.
  std::vector<RawChunk> plain =
      SplitFile(Serialize(testing::MakeTestModel(1, 7, 0), 0));
  ExpectCorrupt(Join(plain, 3), "needs a 'QKNT' or a 'PCTL' chunk");
  // Both knot chunks, or two kinds of control points.
  chunks.insert(chunks.begin() + 1, RawChunk{"KNOT", "x"});
  ExpectCorrupt(Join(chunks), "both a 'KNOT' and a 'QKNT'");
  chunks = SplitFile(file);
  chunks.insert(chunks.begin() + 2, RawChunk{"CTRL", "x"});
  ExpectCorrupt(Join(chunks), "both a 'CTRL' and a 'PCTL' chunk");
}

}  // namespace
}  // namespace sdcb
