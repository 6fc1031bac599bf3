// Tests io/sdcb/sdcb_file.* (format version 2) and io/sdcb/crc32.*: bit-exact
// round trips, deterministic bytes, the documented layout (docs/FORMAT.md,
// decoded here by the independent test-side codec of testing/sdcb_test_codec.h,
// with zlib called directly and the configuration hash recomputed from the
// brute-force oracle's configurations), and hostile files: every single-byte
// corruption and every truncation of a valid file is rejected, crafted files
// with valid CRCs but bad contents are rejected with a message naming the
// problem, and no count or length read from a file leads to an allocation
// larger than the file justifies. Version 1: sdcb_file_v1_test.cpp.
#include "sdcb/io/sdcb/sdcb_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "sdcb/io/report/fit_statistics_json.h"
#include "sdcb/io/sdcb/crc32.h"
#include "testing/allocation_tracker.h"
#include "testing/sdcb_test_codec.h"
#include "testing/spline_model_fixture.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::BitIdentical;
using testing::ExpectCorrupt;
using testing::Find;
using testing::FreshTestDir;
using testing::GetLe;
using testing::GetLeDouble;
using testing::Le;
using testing::LeDouble;
using testing::MakeTestModel;
using testing::RawChunk;
using testing::ReadBytes;
using testing::SameBits;
using testing::SplitFile;
using testing::TestInflate;
using testing::TestPack;
using testing::TestPackPoints;
using testing::TestUnpackPoints;
using testing::WriteBytes;

// zlib's inflater allocates its state (~7 KiB) and a 32 KiB window whatever
// the stream; allocation bounds below allow this constant on top.
constexpr size_t kZlibFixedBytes = 48 * 1024;

std::string Join(const std::vector<RawChunk>& chunks, uint32_t version = 2) {
  return testing::JoinFile(chunks, version);
}

std::string Serialize(const SplineModel& m, const SdcbWriteOptions& o = {}) {
  StatusOr<std::string> bytes = SerializeSdcb(m, o);
  EXPECT_TRUE(bytes.ok()) << bytes.status().message();
  return bytes.ok() ? *bytes : std::string();
}

// ParseSdcb, also reporting the largest single allocation it made.
StatusOr<SplineModel> TrackedParse(const std::string& bytes, size_t* largest) {
  StatusOr<SplineModel> result = InternalError("not parsed");
  *largest =
      testing::LargestAllocationDuring([&] { result = ParseSdcb(bytes); });
  return result;
}

// A model with ordinary control points (within [-0.6, 0.6]^3), which the
// quantizer accepts (MakeTestModel's include the largest doubles).
SplineModel QuantizableModel(int degree = 2, int knots = 10,
                             int parameters = 3) {
  SplineModel m = MakeTestModel(degree, knots, parameters);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  for (Eigen::Index i = 0; i < m.control_points.rows(); ++i) {
    for (int c = 0; c < 3; ++c) m.control_points(i, c) = u(rng);
  }
  return m;
}

// --- CRC-32 -----------------------------------------------------------------

TEST(Crc32Test, KnownValues) {
  EXPECT_EQ(Crc32("123456789"), 0xCBF43926u);  // the standard check value
  EXPECT_EQ(Crc32(""), 0u);
  EXPECT_EQ(Crc32("The quick brown fox jumps over the lazy dog"), 0x414FA339u);
  EXPECT_EQ(Crc32(std::string(1, '\0')), 0xD202EF8Du);
}

TEST(Crc32Test, IncrementalEqualsWhole) {
  const std::string s = "spherical DCB-spline surfaces";
  for (size_t cut = 0; cut <= s.size(); ++cut) {
    EXPECT_EQ(
        Crc32Update(Crc32(s.substr(0, cut)), s.data() + cut, s.size() - cut),
        Crc32(s));
  }
}

// --- Round trips and determinism -------------------------------------------

TEST(SdcbFileTest, RoundTripIsBitIdenticalForEveryDegreeAndBasisForm) {
  for (int k = 0; k <= kMaxSplineDegree; ++k) {
    for (int parameters : {0, 6}) {
      for (BasisForm form : {BasisForm::kNormalized, BasisForm::kRaw}) {
        SplineModel model = MakeTestModel(k, k + 9, parameters, 20 + k);
        model.basis_form = form;
        ASSERT_TRUE(ValidateSplineModel(model).ok());
        const std::string bytes = Serialize(model);
        SdcbFileInfo info;
        const StatusOr<SplineModel> back = ParseSdcb(bytes, &info);
        ASSERT_TRUE(back.ok()) << back.status().message();
        EXPECT_TRUE(BitIdentical(model, *back)) << "degree " << k;
        EXPECT_EQ(info.format_version, 2u);
        EXPECT_EQ(info.file_bytes, bytes.size());
        EXPECT_TRUE(info.quantization.lossless());
        // Re-serializing the parsed model reproduces the bytes.
        EXPECT_EQ(Serialize(*back), bytes);
      }
    }
  }
}

TEST(SdcbFileTest, SpecialDoublesSurviveBitForBit) {
  const SplineModel model = MakeTestModel();
  const StatusOr<SplineModel> back = ParseSdcb(Serialize(model));
  ASSERT_TRUE(back.ok());
  // The fixture put these into the first control points; check them
  // explicitly, not only through BitIdentical.
  EXPECT_TRUE(std::signbit(back->control_points(0, 0)));
  EXPECT_EQ(back->control_points(0, 0), 0.0);
  EXPECT_EQ(back->control_points(0, 1),
            std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(back->control_points(0, 2), -2.5e-310);
  EXPECT_EQ(back->control_points(1, 0), std::numeric_limits<double>::max());
  EXPECT_EQ(back->control_points(1, 1), std::numeric_limits<double>::lowest());
  EXPECT_EQ(back->transform.translation[1], 1e-320);
  EXPECT_EQ(back->statistics.rounds[0].folded_area_percent,
            std::numeric_limits<double>::denorm_min());
  EXPECT_TRUE(std::signbit(back->statistics.options.fairness));  // -0.0
  EXPECT_EQ(back->source.file_name, "meshes/bunny \xc3\xa9.off");
}

TEST(SdcbFileTest, StatisticsJsonIsBitExactForRandomDoubles) {
  // STAT is JSON text; every finite double, drawn as random bit patterns
  // (all exponents, denormals, both signs), must come back unchanged.
  SplineModel model = MakeTestModel();
  std::mt19937_64 rng(5);
  const auto random_double = [&] {
    while (true) {
      const uint64_t bits = rng();
      double d;
      std::memcpy(&d, &bits, 8);
      if (std::isfinite(d)) return d;
    }
  };
  model.statistics.rounds.resize(300);
  for (RoundStatistics& r : model.statistics.rounds) {
    r.rmse_percent = random_double();
    r.max_error_percent = random_double();
    r.vertex_rmse_percent = random_double();
    r.vertex_max_error_percent = random_double();
    r.folded_area_percent = random_double();
    // An open part's (>= 0, written); a closed part's -1 (not written).
    r.boundary_error_percent = (&r - model.statistics.rounds.data()) % 2
                                   ? std::abs(random_double())
                                   : -1.0;
  }
  model.statistics.options.lambda = 0.1 + 0.2;
  model.statistics.options.alpha = 5e-324;
  model.statistics.options.regularization = 1.7976931348623157e308;
  const StatusOr<SplineModel> back = ParseSdcb(Serialize(model));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(BitIdentical(model, *back));
}

TEST(SdcbFileTest, WritingTwiceGivesIdenticalFiles) {
  const std::string dir = FreshTestDir();
  const SplineModel model = MakeTestModel(3, 14, 8);
  ASSERT_TRUE(WriteSdcbFile(model, dir + "/a.sdcb").ok());
  SdcbFileInfo info;
  ASSERT_TRUE(
      WriteSdcbFile(MakeTestModel(3, 14, 8), dir + "/b.sdcb", {}, &info).ok());
  const std::string a = ReadBytes(dir + "/a.sdcb");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, ReadBytes(dir + "/b.sdcb"));
  EXPECT_EQ(a, Serialize(model));
  EXPECT_EQ(info.file_bytes, a.size());
  const StatusOr<SplineModel> back = ReadSdcbFile(dir + "/a.sdcb");
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(BitIdentical(model, *back));
  // Quantized files are deterministic too.
  const SdcbWriteOptions q{true, 12};
  EXPECT_EQ(Serialize(QuantizableModel(), q), Serialize(QuantizableModel(), q));
  // Only the two outputs exist: no temporary files left behind.
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 2);
}

TEST(SdcbFileTest, LayoutMatchesFormatDocument) {
  SplineModel model = MakeTestModel(2, 10, 4);
  model.basis_form = BasisForm::kRaw;
  const std::string file = Serialize(model);
  ASSERT_GE(file.size(), 12u);
  EXPECT_EQ(file.substr(0, 8), std::string("\x89SDCB\r\n\x1a", 8));
  EXPECT_EQ(GetLe(file, 8, 4), 2u);
  std::vector<RawChunk> chunks = SplitFile(file);
  std::vector<std::string> types;
  for (const RawChunk& c : chunks) types.push_back(c.type);
  EXPECT_EQ(types, (std::vector<std::string>{"HEAD", "KNOT", "CTRL", "XFRM",
                                             "STAT", "SRCM", "PARM", "END "}));
  EXPECT_EQ(Join(chunks), file);

  const std::string& head = Find(chunks, "HEAD")->payload;
  ASSERT_EQ(head.size(), 40u);
  EXPECT_EQ(GetLe(head, 0, 4), 2u);  // degree
  EXPECT_EQ(GetLe(head, 4, 4), 1u);  // raw basis
  EXPECT_EQ(GetLe(head, 8, 8), 10u);
  EXPECT_EQ(GetLe(head, 16, 8), model.configurations.sets.size());
  EXPECT_EQ(GetLe(head, 24, 8), 4u);
  // The hash of the (brute-force oracle's) configurations' BSIS bytes.
  EXPECT_EQ(
      GetLe(head, 32, 8),
      testing::TestFnv1a64(testing::TestBasisBytes(model.configurations)));
  EXPECT_EQ(GetLe(head, 32, 8), HashConfigurations(model.configurations));

  // Packed arrays: u64 inflated length, zlib stream of byte planes of the
  // doubles by coordinate.
  const std::string& knots = Find(chunks, "KNOT")->payload;
  EXPECT_EQ(GetLe(knots, 0, 8), 10u * 24);
  EXPECT_TRUE(SameBits(TestUnpackPoints(knots), model.knots));
  const std::string planes = TestInflate(knots);
  // Plane 7 (the sign / high exponent bytes) starts at 7 * 30 values; its
  // entry for knot 3's y is value 10 + 3.
  uint64_t bits;
  const double y3 = model.knots(3, 1);
  std::memcpy(&bits, &y3, 8);
  EXPECT_EQ(static_cast<uint8_t>(planes[7 * 30 + 13]), bits >> 56);
  EXPECT_EQ(static_cast<uint8_t>(planes[0 * 30 + 13]), bits & 0xFF);

  const Eigen::MatrixX3d ctrl = TestUnpackPoints(Find(chunks, "CTRL")->payload);
  EXPECT_TRUE(SameBits(ctrl, model.control_points));
  EXPECT_TRUE(std::signbit(ctrl(0, 0)));

  EXPECT_EQ(Find(chunks, "XFRM")->payload,
            LeDouble(model.transform.scale) +
                LeDouble(model.transform.translation[0]) +
                LeDouble(model.transform.translation[1]) +
                LeDouble(model.transform.translation[2]));

  const std::string stat_text = TestInflate(Find(chunks, "STAT")->payload);
  EXPECT_EQ(stat_text, FitStatisticsToJson(model.statistics).dump());
  const nlohmann::json stat = nlohmann::json::parse(stat_text);
  EXPECT_EQ(stat["rounds"].size(), 3u);
  EXPECT_EQ(stat["final"]["knots"], 300);
  EXPECT_EQ(stat["options"]["regularization"], 12.5);
  EXPECT_EQ(stat["options"]["lambda"], 0.2);

  EXPECT_EQ(Find(chunks, "SRCM")->payload, Le(4, 8) + Le(4, 8) +
                                               Le(0xfedcba9876543210ULL, 8) +
                                               "meshes/bunny \xc3\xa9.off");
  EXPECT_TRUE(SameBits(TestUnpackPoints(Find(chunks, "PARM")->payload),
                       model.parameters));
  EXPECT_TRUE(Find(chunks, "END ")->payload.empty());

  // The reader takes any valid zlib stream (other levels, other writers).
  for (const char* type : {"KNOT", "CTRL", "PARM"}) {
    RawChunk* c = Find(chunks, type);
    c->payload = TestPack(TestInflate(c->payload), 1);
  }
  const StatusOr<SplineModel> back = ParseSdcb(Join(chunks));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(BitIdentical(model, *back));
}

TEST(SdcbFileTest, QuantizedLayoutMatchesFormatDocument) {
  const SplineModel model = QuantizableModel(2, 10, 0);
  SdcbFileInfo info;
  SdcbWriteOptions version2;
  version2.quantize_bits = 10;
  version2.format_version = 2;  // QCTL: version 3 writes PCTL instead
  const StatusOr<std::string> file = SerializeSdcb(model, version2, &info);
  ASSERT_TRUE(file.ok()) << file.status().message();
  std::vector<RawChunk> chunks = SplitFile(*file);
  ASSERT_EQ(Find(chunks, "CTRL"), nullptr);
  ASSERT_NE(Find(chunks, "QCTL"), nullptr);
  const std::string& q = Find(chunks, "QCTL")->payload;
  ASSERT_GE(q.size(), 68u + 8);
  EXPECT_EQ(GetLe(q, 0, 4), 10u);
  Eigen::Vector3d origin, step;
  for (int c = 0; c < 3; ++c) {
    origin[c] = GetLeDouble(q, 4 + 8 * c);
    step[c] = GetLeDouble(q, 28 + 8 * c);
    // The grid spans the control points' bounding box in 1023 steps.
    EXPECT_EQ(origin[c], model.control_points.col(c).minCoeff());
    EXPECT_NEAR(origin[c] + 1023 * step[c],
                model.control_points.col(c).maxCoeff(), 1e-15);
  }
  const double displacement = GetLeDouble(q, 52);
  EXPECT_EQ(GetLeDouble(q, 60), 1.0);  // normalized basis: sum 1
  EXPECT_EQ(displacement, info.quantization.max_displacement);
  EXPECT_EQ(info.quantization.surface_error_bound(), displacement);
  // Codes: zigzag differences from the previous control point's code, per
  // coordinate, u32 byte planes.
  const std::string codes =
      testing::TestFromPlanes(TestInflate(q.substr(68)), 4);
  const Eigen::Index m = model.control_points.rows();
  ASSERT_EQ(codes.size(), static_cast<size_t>(12 * m));
  Eigen::MatrixX3d decoded(m, 3);
  double largest = 0;
  for (int c = 0; c < 3; ++c) {
    uint32_t code = 0;
    for (Eigen::Index i = 0; i < m; ++i) {
      const auto z = static_cast<uint32_t>(GetLe(codes, 4 * (c * m + i), 4));
      code += (z & 1) ? ~(z >> 1) : (z >> 1);
      ASSERT_LT(code, 1024u);
      decoded(i, c) = origin[c] + code * step[c];
    }
  }
  for (Eigen::Index i = 0; i < m; ++i) {
    largest = std::max(largest,
                       (decoded.row(i) - model.control_points.row(i)).norm());
  }
  // The stated displacement is the true one, at most half a cell diagonal.
  EXPECT_EQ(displacement, largest);
  EXPECT_LE(displacement, 0.5 * step.norm() * (1 + 1e-12));
  SdcbFileInfo read_info;
  const StatusOr<SplineModel> back = ParseSdcb(*file, &read_info);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(SameBits(back->control_points, decoded));
  EXPECT_EQ(read_info.quantization.bits, 10);
  EXPECT_EQ(read_info.quantization.max_displacement, displacement);
  EXPECT_FALSE(read_info.quantization.basis_sum_measured);
  // Everything but the control points is exact.
  SplineModel expected = model;
  expected.control_points = decoded;
  EXPECT_TRUE(BitIdentical(expected, *back));
}

TEST(SdcbFileTest, ParametersAreStoredOnlyWhenAskedAndPresent) {
  const SplineModel with = MakeTestModel(1, 7, 5);
  for (bool store : {true, false}) {
    const std::string file = Serialize(with, {store, 0});
    std::vector<RawChunk> chunks = SplitFile(file);
    EXPECT_EQ(Find(chunks, "PARM") != nullptr, store);
    EXPECT_EQ(GetLe(Find(chunks, "HEAD")->payload, 24, 8), store ? 5u : 0u);
    const StatusOr<SplineModel> back = ParseSdcb(file);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(back->parameters.rows(), store ? 5 : 0);
  }
  std::vector<RawChunk> without = SplitFile(Serialize(MakeTestModel(1, 7, 0)));
  EXPECT_EQ(Find(without, "PARM"), nullptr);
}

TEST(SdcbFileTest, WriterRefusesWhatItCannotWriteFaithfully) {
  const SplineModel model = MakeTestModel(2, 10, 0);
  // Configurations that are valid but not those of the knots.
  SplineModel other = model;
  other.configurations.sets.pop_back();
  other.control_points.conservativeResize(other.control_points.rows() - 1, 3);
  ASSERT_TRUE(ValidateSplineModel(other).ok());
  StatusOr<std::string> s = SerializeSdcb(other);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.status().message().find("not those of its knots"),
            std::string::npos)
      << s.status().message();
  other = model;
  other.configurations.sets[0].boundaries.pop_back();
  if (!other.configurations.sets[0].boundaries.empty()) {
    EXPECT_FALSE(SerializeSdcb(other).ok());
  }
  for (int bits : {-2, 33, 64}) {
    s = SerializeSdcb(QuantizableModel(), {true, bits});
    ASSERT_FALSE(s.ok()) << bits;
    EXPECT_EQ(s.status().code(), StatusCode::kInvalidArgument);
  }
  // Control points spanning more than the double range.
  SplineModel huge = model;
  huge.control_points(0, 0) = std::numeric_limits<double>::max();
  huge.control_points(1, 0) = std::numeric_limits<double>::lowest();
  s = SerializeSdcb(huge, {true, 16});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("too large"), std::string::npos);
  for (int bits : {1, 32}) {
    EXPECT_TRUE(SerializeSdcb(QuantizableModel(), {true, bits}).ok()) << bits;
  }
}

// --- Hostile input ---------------------------------------------------------

TEST(SdcbFileTest, EverySingleByteCorruptionIsRejected) {
  for (int quantize : {0, 12}) {
    const SplineModel model = QuantizableModel(1, 7, 3);
    const std::string file = Serialize(model, {true, quantize});
    ASSERT_LT(file.size(), 4000u);  // keep the loop quick
    const StatusOr<SplineModel> reference = ParseSdcb(file);
    ASSERT_TRUE(reference.ok());
    const size_t largest =
        testing::ExpectEverySingleByteCorruptionRejected(file, *reference);
    // Nothing read from a corrupt file made an allocation beyond a small
    // multiple of its size.
    EXPECT_LT(largest, 16 * file.size() + 4096);
  }
}

TEST(SdcbFileTest, EveryTruncationIsRejected) {
  for (int quantize : {0, 20}) {
    const std::string file =
        Serialize(QuantizableModel(2, 9, 2), {true, quantize});
    for (size_t length = 0; length < file.size(); ++length) {
      const StatusOr<SplineModel> m = ParseSdcb(file.substr(0, length));
      ASSERT_FALSE(m.ok()) << "accepted a file cut to " << length << " bytes";
      EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile);
    }
    ExpectCorrupt(file.substr(0, file.size() - 1), "truncated");
    ExpectCorrupt(file.substr(0, file.size() - 16), "before the END chunk");
  }
}

TEST(SdcbFileTest, UnknownChunksAreSkipped) {
  const SplineModel model = MakeTestModel(2, 9, 2);
  std::vector<RawChunk> chunks = SplitFile(Serialize(model));
  chunks.insert(chunks.begin() + 1,
                RawChunk{"note", "added by a newer writer"});
  chunks.insert(chunks.end() - 1,
                RawChunk{"ZZ_9", std::string("\0\xff\x01 binary", 10)});
  chunks.insert(chunks.end() - 1, RawChunk{"EMPT", ""});
  // Version 1's configuration chunk means nothing to version 2.
  chunks.insert(chunks.end() - 1, RawChunk{"BSIS", "not read"});
  const std::string file = Join(chunks);
  const StatusOr<SplineModel> back = ParseSdcb(file);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(BitIdentical(model, *back));
  // An unknown chunk is still CRC-checked.
  std::string bad = file;
  bad[bad.find("added by")] ^= 0x20;
  ExpectCorrupt(bad, "'note'");
  ExpectCorrupt(bad, "CRC");
}

TEST(SdcbFileTest, ChunksBetweenHeadAndEndMayComeInAnyOrder) {
  const SplineModel model = MakeTestModel(2, 9, 2);
  std::vector<RawChunk> chunks = SplitFile(Serialize(model));
  std::reverse(chunks.begin() + 1, chunks.end() - 1);
  ASSERT_EQ(chunks[1].type, "PARM");
  const StatusOr<SplineModel> back = ParseSdcb(Join(chunks));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_TRUE(BitIdentical(model, *back));
}

TEST(SdcbFileTest, AbsurdCountsAreRejectedWithoutAllocating) {
  const std::string file = Serialize(MakeTestModel(1, 7, 3));
  // The tracker sees the reader's allocations: a valid parse allocates the
  // 7 x 3 knot matrix at least.
  size_t valid_largest = 0;
  ASSERT_TRUE(TrackedParse(file, &valid_largest).ok());
  EXPECT_GE(valid_largest, 7u * 24);
  struct Case {
    size_t offset;  // within the HEAD payload
    uint64_t value;
    const char* what;
  };
  // Packed data inflates at most 1032-fold: the counts must fit
  // 1032 x the file's bytes (24 bytes per knot / parameter, 12 per basis
  // function).
  const uint64_t limit = 1032 * file.size();
  const Case cases[] = {
      {8, uint64_t{1} << 60, "knots"},
      {8, limit / 24 + 1, "knots"},
      {16, uint64_t{1} << 60, "basis functions"},
      {16, limit / 12 + 1, "basis functions"},
      {24, uint64_t{1} << 62, "sphere parameters"},
      {24, limit / 24 + 1, "sphere parameters"},
  };
  for (const Case& c : cases) {
    std::vector<RawChunk> chunks = SplitFile(file);
    Find(chunks, "HEAD")->payload.replace(c.offset, 8, Le(c.value, 8));
    size_t largest = 0;
    const StatusOr<SplineModel> m = TrackedParse(Join(chunks), &largest);
    ASSERT_FALSE(m.ok()) << c.what << " " << c.value;
    EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile);
    EXPECT_NE(m.status().message().find(std::to_string(c.value) + " " + c.what +
                                        ", more than the file's"),
              std::string::npos)
        << m.status().message();
    EXPECT_LT(largest, 16 * file.size() + 4096) << c.what << " " << c.value;
  }
  // Counts the file could hold, but that disagree with the chunks: refused
  // by the chunk's declared inflated length, before inflating.
  for (const Case& c : {Case{8, 9, "knots"}, Case{16, 40, "basis functions"},
                        Case{24, 4, "sphere parameters"}}) {
    std::vector<RawChunk> chunks = SplitFile(file);
    Find(chunks, "HEAD")->payload.replace(c.offset, 8, Le(c.value, 8));
    ExpectCorrupt(Join(chunks), "inflated bytes; the declared counts need");
  }
}

TEST(SdcbFileTest, InflatingNeverExceedsTheDeclaredSize) {
  const std::string file = Serialize(MakeTestModel(1, 7, 3));
  const auto with_stat = [&](const std::string& payload) {
    std::vector<RawChunk> chunks = SplitFile(file);
    Find(chunks, "STAT")->payload = payload;
    return Join(chunks);
  };
  // A zip bomb: 64 MiB of spaces (valid JSON whitespace) in ~64 KiB, which
  // declares 64 bytes. The reader stops at 64 bytes and allocates little.
  const std::string bomb = TestPack(std::string(64 << 20, ' '));
  ASSERT_LT(bomb.size(), 100'000u);
  std::string declared_small = Le(64, 8) + bomb.substr(8);
  size_t largest = 0;
  StatusOr<SplineModel> m = TrackedParse(with_stat(declared_small), &largest);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("inflates to more than its 64 declared"),
            std::string::npos)
      << m.status().message();
  EXPECT_LT(largest, kZlibFixedBytes + 16 * file.size());
  // The same bomb declaring its true size is refused only by the JSON
  // parser, after inflating exactly what it declared.
  m = ParseSdcb(with_stat(bomb));
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("STAT chunk is not valid JSON"),
            std::string::npos)
      << m.status().message();
  // Declaring more than deflate can produce is refused before inflating.
  const std::string small = TestPack("{}");
  ExpectCorrupt(
      with_stat(Le(1032 * (small.size() - 8) + 1, 8) + small.substr(8)),
      "more than deflate allows");
  // Declaring more than the stream holds: refused when it ends, allocation
  // bounded by what was produced.
  const std::string stat = SplitFile(file)[4].payload;
  ASSERT_EQ(SplitFile(file)[4].type, "STAT");
  const std::string longer = Le(GetLe(stat, 0, 8) * 100, 8) + stat.substr(8);
  m = TrackedParse(with_stat(longer), &largest);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("bytes, not its"), std::string::npos)
      << m.status().message();
  EXPECT_LT(largest, kZlibFixedBytes + 16 * file.size());
  // Declaring less than the stream holds.
  ExpectCorrupt(with_stat(Le(GetLe(stat, 0, 8) - 1, 8) + stat.substr(8)),
                "inflates to more than its");
  // A stream whose Adler-32 is wrong, bytes after the stream, no stream.
  std::string bad_adler = stat;
  bad_adler.back() ^= 1;
  ExpectCorrupt(with_stat(bad_adler), "zlib stream is corrupt");
  ExpectCorrupt(with_stat(stat + "x"), "1 bytes follow the end of a zlib");
  ExpectCorrupt(with_stat(stat.substr(0, 8)), "more than deflate allows");
  ExpectCorrupt(with_stat(stat.substr(0, stat.size() - 3)), "ends early");
  ExpectCorrupt(with_stat("1234567"), "too few for its inflated length");
  std::string garbage = stat;
  garbage[9] ^= 0x40;  // the zlib header's check bits
  ExpectCorrupt(with_stat(garbage), "zlib stream is corrupt");
}

TEST(SdcbFileTest, CraftedFilesWithValidCrcsAreRejected) {
  const SplineModel model = MakeTestModel(1, 7, 3);
  const std::string file = Serialize(model);
  const auto edit = [&](const std::string& type, auto change) {
    std::vector<RawChunk> chunks = SplitFile(file);
    change(Find(chunks, type)->payload);
    return Join(chunks);
  };
  const auto edit_points = [&](const std::string& type, auto change) {
    return edit(type, [&](std::string& p) {
      Eigen::MatrixX3d points = TestUnpackPoints(p);
      change(points);
      p = TestPackPoints(points);
    });
  };
  // Configurations: the stored hash must match the recomputed ones.
  ExpectCorrupt(edit("HEAD",
                     [](std::string& p) {
                       p[32] ^= 1;  // the hash's lowest byte
                     }),
                "the configurations recomputed from the knots have hash");
  // A knot moved to another unit vector: other configurations (different
  // count or hash).
  {
    const std::string moved =
        edit_points("KNOT", [](Eigen::MatrixX3d& k) { k.row(0) = -k.row(0); });
    const StatusOr<SplineModel> m = ParseSdcb(moved);
    ASSERT_FALSE(m.ok());
    const std::string& message = m.status().message();
    EXPECT_TRUE(message.find("have hash") != std::string::npos ||
                message.find("basis functions but HEAD declares") !=
                    std::string::npos)
        << message;
  }
  // A knot moved by one unit in the last place: same configurations, the
  // file is valid (the knots are data; the hash guards the structure).
  {
    const StatusOr<SplineModel> m =
        ParseSdcb(edit_points("KNOT", [](Eigen::MatrixX3d& k) {
          k(2, 0) = std::nextafter(k(2, 0), 2.0);
        }));
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_NE(m->knots(2, 0), model.knots(2, 0));
  }
  // More control points and a HEAD that agrees: the knots define fewer.
  {
    std::vector<RawChunk> chunks = SplitFile(file);
    const uint64_t m = model.configurations.sets.size();
    Find(chunks, "HEAD")->payload.replace(16, 8, Le(m + 1, 8));
    Eigen::MatrixX3d more(m + 1, 3);
    more << model.control_points, Eigen::RowVector3d(0.1, 0.2, 0.3);
    Find(chunks, "CTRL")->payload = TestPackPoints(more);
    ExpectCorrupt(Join(chunks), "the knots define " + std::to_string(m) +
                                    " basis functions but HEAD declares " +
                                    std::to_string(m + 1));
  }
  // Knots that do not define configurations.
  ExpectCorrupt(
      edit_points("KNOT", [](Eigen::MatrixX3d& k) { k.row(1) = k.row(0); }),
      "the configurations cannot be recomputed from the knots");
  ExpectCorrupt(edit_points("KNOT", [](Eigen::MatrixX3d& k) { k(0, 0) = 2; }),
                "knot 0 is not a unit vector");
  ExpectCorrupt(
      edit_points("KNOT", [](Eigen::MatrixX3d& k) { k(0, 0) = std::nan(""); }),
      "knot 0 is not a unit vector");
  {
    std::vector<RawChunk> chunks = SplitFile(file);
    Find(chunks, "HEAD")->payload.replace(8, 8, Le(4, 8));
    Find(chunks, "KNOT")->payload = TestPackPoints(model.knots.topRows(4));
    ExpectCorrupt(Join(chunks), "degree 1 needs at least 5");
  }
  ExpectCorrupt(
      edit_points("CTRL", [](Eigen::MatrixX3d& c) { c(1, 0) = std::nan(""); }),
      "control point coordinate is not finite");
  ExpectCorrupt(edit_points("PARM", [](Eigen::MatrixX3d& c) { c(1, 2) = 3; }),
                "sphere parameter of vertex 1 is not a unit vector");
  ExpectCorrupt(
      edit("XFRM", [](std::string& p) { p.replace(0, 8, LeDouble(-1.0)); }),
      "finite scale > 0");
  ExpectCorrupt(edit("XFRM", [](std::string& p) { p += "x"; }),
                "the XFRM chunk has 33 bytes");
  ExpectCorrupt(edit("HEAD", [](std::string& p) { p.replace(0, 4, Le(6, 4)); }),
                "degree 6");
  ExpectCorrupt(edit("HEAD", [](std::string& p) { p.replace(0, 4, Le(2, 4)); }),
                "");  // degree 2: other configurations
  ExpectCorrupt(edit("HEAD", [](std::string& p) { p.replace(4, 4, Le(7, 4)); }),
                "unknown basis form 7");
  ExpectCorrupt(edit("HEAD", [](std::string& p) { p.pop_back(); }),
                "version 2 needs 40");
  const auto edit_stat = [&](auto change) {
    return edit("STAT", [&](std::string& p) {
      std::string text = TestInflate(p);
      change(text);
      p = TestPack(text);
    });
  };
  ExpectCorrupt(edit_stat([](std::string& t) { t.pop_back(); }),
                "STAT chunk is not valid JSON");
  ExpectCorrupt(edit_stat([](std::string& t) {
                  auto j = nlohmann::json::parse(t);
                  j["options"].erase("lambda");
                  t = j.dump();
                }),
                "statistics.options lacks the key \"lambda\"");
  ExpectCorrupt(edit_stat([](std::string& t) {
                  auto j = nlohmann::json::parse(t);
                  j["rounds"][1]["knots"] = "many";
                  t = j.dump();
                }),
                "statistics.rounds[1].knots is not an integer");
  ExpectCorrupt(edit_stat([](std::string& t) {
                  auto j = nlohmann::json::parse(t);
                  j["final"]["round"] = uint64_t{1} << 40;
                  t = j.dump();
                }),
                "statistics.final.round is out of range");
  // Deeply nested JSON must not exhaust the stack.
  ExpectCorrupt(edit_stat([](std::string& t) {
                  t = std::string(200000, '[') + std::string(200000, ']');
                }),
                "statistics is not a JSON object");
  ExpectCorrupt(edit_stat([](std::string& t) { t = "{\"rounds\": 1e999}"; }),
                "STAT chunk");
  ExpectCorrupt(edit("SRCM", [](std::string& p) { p.resize(20); }),
                "the SRCM chunk has 20 bytes");
}

TEST(SdcbFileTest, CraftedQuantizedChunksAreRejected) {
  const SplineModel model = QuantizableModel(1, 7, 0);
  SdcbWriteOptions version2;
  version2.quantize_bits = 8;
  version2.format_version = 2;  // QCTL
  const std::string file = Serialize(model, version2);
  const auto edit = [&](auto change) {
    std::vector<RawChunk> chunks = SplitFile(file);
    change(Find(chunks, "QCTL")->payload);
    return Join(chunks);
  };
  ExpectCorrupt(edit([](std::string& p) { p.replace(0, 4, Le(0, 4)); }),
                "declares 0 bits");
  ExpectCorrupt(edit([](std::string& p) { p.replace(0, 4, Le(33, 4)); }),
                "declares 33 bits");
  // Fewer bits than the codes need.
  ExpectCorrupt(edit([](std::string& p) { p.replace(0, 4, Le(2, 4)); }),
                "exceeds 2 bits");
  ExpectCorrupt(edit([](std::string& p) { p.replace(28, 8, LeDouble(-1e-3)); }),
                "finite steps >= 0");
  ExpectCorrupt(
      edit([](std::string& p) { p.replace(4, 8, LeDouble(INFINITY)); }),
      "finite origin");
  ExpectCorrupt(edit([](std::string& p) { p.replace(52, 8, LeDouble(-1.0)); }),
                "error bound is invalid");
  // The normalized basis sums to exactly 1.
  ExpectCorrupt(edit([](std::string& p) { p.replace(60, 8, LeDouble(1.5)); }),
                "error bound is invalid");
  ExpectCorrupt(edit([](std::string& p) { p.resize(60); }),
                "the QCTL chunk has 60 bytes");
  ExpectCorrupt(edit([](std::string& p) {
                  std::string codes = TestInflate(p.substr(68));
                  codes.resize(codes.size() - 12);
                  p = p.substr(0, 68) + TestPack(codes);
                }),
                "inflated bytes; the declared counts need");
  // A raw-basis file may state any positive basis sum.
  {
    std::vector<RawChunk> chunks = SplitFile(file);
    Find(chunks, "HEAD")->payload.replace(4, 4, Le(1, 4));
    Find(chunks, "QCTL")->payload.replace(60, 8, LeDouble(1.5));
    SdcbFileInfo info;
    const StatusOr<SplineModel> m = ParseSdcb(Join(chunks), &info);
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_EQ(m->basis_form, BasisForm::kRaw);
    EXPECT_TRUE(info.quantization.basis_sum_measured);
    EXPECT_EQ(info.quantization.surface_error_bound(),
              1.5 * info.quantization.max_displacement);
    Find(chunks, "QCTL")->payload.replace(60, 8, LeDouble(0.0));
    ExpectCorrupt(Join(chunks), "error bound is invalid");
  }
}

TEST(SdcbFileTest, RandomMutationsWithValidCrcsNeverCrash) {
  // Structure-aware fuzzing at two levels: change, insert or drop bytes in
  // one chunk's stored payload, or in the inflated content of a packed chunk
  // (then packed again), and recompute the CRC, so only the content checks
  // stand between the bytes and the model. Whatever is accepted must be a
  // valid model that writes back and reads unchanged.
  for (int quantize : {0, 12}) {
    const std::vector<RawChunk> good =
        SplitFile(Serialize(QuantizableModel(1, 7, 3), {true, quantize}));
    // Quantized files are version 3 (PCTL).
    const uint32_t version = quantize > 0 ? 3 : 2;
    const size_t good_size = Join(good, version).size();
    std::mt19937 rng(11 + quantize);
    int accepted = 0;
    size_t largest_overall = 0;
    constexpr int kIterations = 10000;
    for (int iteration = 0; iteration < kIterations; ++iteration) {
      std::vector<RawChunk> chunks = good;
      RawChunk& chunk = chunks[rng() % chunks.size()];
      const bool packed = chunk.type == "KNOT" || chunk.type == "CTRL" ||
                          chunk.type == "STAT" || chunk.type == "PARM";
      const bool inner = packed && rng() % 2 == 0;
      std::string content = inner ? TestInflate(chunk.payload) : chunk.payload;
      testing::MutateBytes(&rng, &content);
      chunk.payload = inner ? TestPack(content) : content;
      size_t largest = 0;
      const StatusOr<SplineModel> m =
          TrackedParse(Join(chunks, version), &largest);
      largest_overall = std::max(largest_overall, largest);
      if (!m.ok()) {
        EXPECT_FALSE(m.status().message().empty());
        continue;
      }
      ++accepted;
      testing::ExpectWritesBackFaithfully(*m);
    }
    EXPECT_LT(largest_overall, kZlibFixedBytes + 16 * good_size);
    // Some mutations are harmless (a control point's low bits, the file
    // name); most are not. Both kinds must have been exercised.
    EXPECT_GT(accepted, 100) << quantize;
    EXPECT_LT(accepted, kIterations - 100) << quantize;
  }
}

TEST(SdcbFileTest, ChunkStructureViolationsAreRejected) {
  const SplineModel model = MakeTestModel(1, 7, 3);
  const std::vector<RawChunk> good = SplitFile(Serialize(model));
  {
    std::vector<RawChunk> c = good;
    c.insert(c.end() - 1, *Find(c, "XFRM"));
    ExpectCorrupt(Join(c), "chunk 'XFRM' occurs twice");
  }
  for (const char* required : {"KNOT", "XFRM", "SRCM"}) {
    std::vector<RawChunk> c = good;
    c.erase(c.begin() + (Find(c, required) - c.data()));
    ExpectCorrupt(Join(c), std::string("the required chunk '") + required +
                               "' is missing");
  }
  {
    std::vector<RawChunk> c = good;
    c.erase(c.begin() + (Find(c, "CTRL") - c.data()));
    ExpectCorrupt(Join(c), "the required chunk 'CTRL' (or 'QCTL') is missing");
  }
  {
    std::vector<RawChunk> c = good;
    SdcbWriteOptions version2;
    version2.quantize_bits = 8;
    version2.format_version = 2;
    const std::vector<RawChunk> q =
        SplitFile(Serialize(QuantizableModel(1, 7, 3), version2));
    c.insert(c.end() - 1, q[2]);
    ASSERT_EQ(q[2].type, "QCTL");
    ExpectCorrupt(Join(c), "both a 'CTRL' and a 'QCTL' chunk");
  }
  {
    std::vector<RawChunk> c = good;
    c.pop_back();  // END
    ExpectCorrupt(Join(c), "before the END chunk");
  }
  {
    std::vector<RawChunk> c = good;
    std::swap(c[0], c[1]);
    ExpectCorrupt(Join(c), "the first chunk is 'KNOT'");
  }
  {
    std::vector<RawChunk> c = good;
    c.erase(c.begin() + (Find(c, "PARM") - c.data()));
    ExpectCorrupt(Join(c), "PARM chunk is missing");
  }
  {
    std::vector<RawChunk> c = SplitFile(Serialize(MakeTestModel(1, 7, 0)));
    c.insert(c.end() - 1, RawChunk{"PARM", ""});
    ExpectCorrupt(Join(c), "PARM chunk is present");
  }
  {
    std::vector<RawChunk> c = good;
    Find(c, "END ")->payload = "x";
    ExpectCorrupt(Join(c), "END chunk is not empty");
  }
  ExpectCorrupt(Join(good) + "extra", "5 unexpected bytes follow");
  {
    std::vector<RawChunk> c = good;
    c.insert(c.end() - 1, RawChunk{std::string("B\0D!", 4), ""});
    ExpectCorrupt(Join(c), "invalid type 'B\\x00D!'");
  }
  // STAT is optional: without it the statistics are the defaults.
  {
    std::vector<RawChunk> c = good;
    c.erase(c.begin() + (Find(c, "STAT") - c.data()));
    const StatusOr<SplineModel> m = ParseSdcb(Join(c));
    ASSERT_TRUE(m.ok()) << m.status().message();
    EXPECT_TRUE(m->statistics.rounds.empty());
    EXPECT_EQ(m->statistics.options.degree, 0);
    EXPECT_TRUE(SameBits(m->control_points, model.control_points));
  }
  // A version 2 file labelled version 1 is read as version 1 and refused.
  ExpectCorrupt(Join(good, 1), "the required chunk 'BSIS' is missing");
}

TEST(SdcbFileTest, HeaderProblemsAreNamed) {
  const std::vector<RawChunk> chunks = SplitFile(Serialize(MakeTestModel()));
  const StatusOr<SplineModel> newer = ParseSdcb(Join(chunks, 5));
  ASSERT_FALSE(newer.ok());
  EXPECT_EQ(newer.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(newer.status().message().find("format version 5"),
            std::string::npos);
  EXPECT_NE(newer.status().message().find("up to 4"), std::string::npos);
  ExpectCorrupt(Join(chunks, 0), "format version is 0");
  ExpectCorrupt("", "the file is empty");
  ExpectCorrupt(std::string(kSdcbMagic, 5), "only 5 bytes");
  ExpectCorrupt(std::string(kSdcbMagic, 8) + "\x01", "only 9 bytes");
  ExpectCorrupt("\x89SDCX", "magic number");
  ExpectCorrupt("OFF\n4 4 0\n", "magic number");
  // A text-mode transfer turning CR LF into LF.
  std::string mangled = Join(chunks);
  mangled.erase(5, 1);
  ExpectCorrupt(mangled, "text-mode transfer");
}

// --- Files ------------------------------------------------------------------

TEST(SdcbFileTest, FileErrorsNameThePathAndLeaveNoPartialFile) {
  const std::string dir = FreshTestDir();
  const std::string path = dir + "/model.sdcb";
  const SplineModel model = MakeTestModel();

  const StatusOr<SplineModel> missing = ReadSdcbFile(dir + "/none.sdcb");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kIoError);
  EXPECT_EQ(missing.status().message().rfind(dir + "/none.sdcb: ", 0), 0u);

  const StatusOr<SplineModel> directory = ReadSdcbFile(dir);
  ASSERT_FALSE(directory.ok());
  EXPECT_EQ(directory.status().code(), StatusCode::kIoError);

  // An invalid model is refused and nothing is written.
  SplineModel invalid = model;
  invalid.control_points(0, 0) = std::nan("");
  const Status refused = WriteSdcbFile(invalid, path);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(
      refused.message().rfind(path + ": cannot write an invalid model", 0), 0u);
  EXPECT_FALSE(std::filesystem::exists(path));

  // A failed write leaves an existing file untouched.
  ASSERT_TRUE(WriteSdcbFile(model, path).ok());
  const std::string before = ReadBytes(path);
  EXPECT_FALSE(WriteSdcbFile(invalid, path).ok());
  EXPECT_EQ(ReadBytes(path), before);
  EXPECT_FALSE(WriteSdcbFile(model, dir + "/no/such/dir/m.sdcb").ok());

  // A truncated file on disk: corrupt, message starts with the path.
  const std::string cut = dir + "/cut.sdcb";
  WriteBytes(cut, before.substr(0, before.size() / 2));
  const StatusOr<SplineModel> truncated = ReadSdcbFile(cut);
  ASSERT_FALSE(truncated.ok());
  EXPECT_EQ(truncated.status().code(), StatusCode::kCorruptFile);
  EXPECT_EQ(truncated.status().message().rfind(cut + ": ", 0), 0u);
}

}  // namespace
}  // namespace sdcb
