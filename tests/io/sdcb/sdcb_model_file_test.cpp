// Tests format version 4 (docs/FORMAT.md): a Model of parts with names and
// trim loops. The expected bytes are assembled by the test-side codec
// (testing/sdcb_test_codec.h) from the document's layout; a one-part model
// must give exactly the bytes of SerializeSdcb; every older file reads as a
// one-part model; damaged, truncated and crafted version 4 files are refused
// with kCorruptFile and a message naming the problem.
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/allocation_tracker.h"
#include "testing/sdcb_test_codec.h"
#include "testing/spline_model_fixture.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::BitIdentical;
using testing::Le;
using testing::RawChunk;
using testing::SameBits;
using testing::SplitFile;

// A loop of `n` points on the circle at polar angle `polar` about `axis`
// (any valid loop: the format stores points, not regions).
TrimLoop CircleLoop(const Eigen::Vector3d& axis, double polar, int n) {
  const Eigen::Vector3d z = axis.normalized();
  const Eigen::Vector3d x = z.unitOrthogonal();
  const Eigen::Vector3d y = z.cross(x);
  TrimLoop loop;
  loop.points.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = -2 * M_PI * i / n;
    const Eigen::Vector3d p =
        std::cos(polar) * z +
        std::sin(polar) * (std::cos(a) * x + std::sin(a) * y);
    loop.points.row(i) = p.normalized().transpose();
  }
  return loop;
}

Model TwoPartModel() {
  Model m;
  m.parts.resize(2);
  m.parts[0].name = "left ear";
  m.parts[0].spline = testing::MakeTestModel(1, 7, 5, 7);
  m.parts[1].name =
      "r\xc3\xbc"
      "ckseite \xe2\x9c\x93";  // UTF-8
  m.parts[1].spline = testing::MakeTestModel(2, 8, 0, 11);
  m.parts[1].trims = {CircleLoop({0, 0, 1}, 0.3, 5),
                      CircleLoop({1, 0.2, -0.3}, 0.5, 7)};
  // A -0.0 coordinate must survive.
  m.parts[1].trims[0].points(0, 0) = -0.0;
  m.parts[1].trims[0].points(0, 1) = 0.0;
  m.parts[1].trims[0].points(0, 2) = 1.0;
  m.source.num_vertices = 1000;
  m.source.num_faces = 1990;
  m.source.hash = 0x0123456789abcdefULL;
  m.source.file_name = "scans/two parts.ply";
  return m;
}

std::string Serialize(const Model& m, const SdcbWriteOptions& o = {},
                      SdcbFileInfo* info = nullptr) {
  StatusOr<std::string> bytes = SerializeSdcbModel(m, o, info);
  EXPECT_TRUE(bytes.ok()) << bytes.status().message();
  return bytes.ok() ? *bytes : std::string();
}

void ExpectSameModel(const Model& a, const Model& b) {
  ASSERT_EQ(a.parts.size(), b.parts.size());
  for (size_t i = 0; i < a.parts.size(); ++i) {
    EXPECT_EQ(a.parts[i].name, b.parts[i].name) << i;
    EXPECT_TRUE(BitIdentical(a.parts[i].spline, b.parts[i].spline)) << i;
    ASSERT_EQ(a.parts[i].trims.size(), b.parts[i].trims.size()) << i;
    for (size_t t = 0; t < a.parts[i].trims.size(); ++t) {
      EXPECT_TRUE(
          SameBits(a.parts[i].trims[t].points, b.parts[i].trims[t].points))
          << i << " " << t;
    }
  }
  EXPECT_EQ(a.source.num_vertices, b.source.num_vertices);
  EXPECT_EQ(a.source.num_faces, b.source.num_faces);
  EXPECT_EQ(a.source.hash, b.source.hash);
  EXPECT_EQ(a.source.file_name, b.source.file_name);
}

// SRCM from docs/FORMAT.md: u64 vertices, u64 faces, u64 hash, the name.
std::string SourceBytes(const SourceMeshInfo& s) {
  return Le(s.num_vertices, 8) + Le(s.num_faces, 8) + Le(s.hash, 8) +
         s.file_name;
}

// A chunk sequence without the file header.
std::string Sequence(const std::vector<RawChunk>& chunks) {
  return testing::JoinFile(chunks, 0).substr(12);
}

// TRIM from docs/FORMAT.md: u64 L, L u64 counts, the points packed.
std::string TrimBytes(const std::vector<TrimLoop>& loops) {
  std::string s = Le(loops.size(), 8);
  Eigen::Index total = 0;
  for (const TrimLoop& l : loops) {
    s += Le(l.points.rows(), 8);
    total += l.points.rows();
  }
  Eigen::MatrixX3d all(total, 3);
  Eigen::Index row = 0;
  for (const TrimLoop& l : loops) {
    all.middleRows(row, l.points.rows()) = l.points;
    row += l.points.rows();
  }
  return s + testing::TestPackPoints(all);
}

// A PART payload: the part spline's chunks as its own version 2/3 file
// holds them (without END), then NAME and TRIM when present, then END.
std::string PartBytes(const ModelPart& part) {
  StatusOr<std::string> spline = SerializeSdcb(part.spline);
  EXPECT_TRUE(spline.ok());
  std::vector<RawChunk> chunks = SplitFile(*spline);
  chunks.pop_back();  // END
  if (!part.name.empty()) chunks.push_back({"NAME", part.name});
  if (part.trimmed()) chunks.push_back({"TRIM", TrimBytes(part.trims)});
  chunks.push_back({"END ", ""});
  return Sequence(chunks);
}

std::vector<RawChunk> ExpectedChunks(const Model& m) {
  std::vector<RawChunk> chunks = {{"HEAD", Le(m.parts.size(), 8)},
                                  {"SRCM", SourceBytes(m.source)}};
  for (const ModelPart& p : m.parts) chunks.push_back({"PART", PartBytes(p)});
  chunks.push_back({"END ", ""});
  return chunks;
}

std::string Join4(const std::vector<RawChunk>& chunks) {
  return testing::JoinFile(chunks, 4);
}

void ExpectCorruptModel(const std::string& file, const std::string& fragment) {
  const StatusOr<Model> m = ParseSdcbModel(file);
  ASSERT_FALSE(m.ok()) << "accepted a file that should fail with: " << fragment;
  EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile)
      << m.status().message();
  EXPECT_NE(m.status().message().find(fragment), std::string::npos)
      << "message: " << m.status().message()
      << "\nexpected to contain: " << fragment;
}

TEST(SdcbModelFileTest, TwoPartsWithNamesAndTrimsRoundTripBitExactly) {
  const Model model = TwoPartModel();
  SdcbFileInfo info;
  const std::string file = Serialize(model, {}, &info);
  EXPECT_EQ(testing::GetLe(file, 8, 4), 4u);
  EXPECT_EQ(info.format_version, 4u);
  EXPECT_EQ(info.file_bytes, file.size());
  EXPECT_EQ(info.parts.size(), 2u);
  SdcbFileInfo read_info;
  const StatusOr<Model> read = ParseSdcbModel(file, &read_info);
  ASSERT_TRUE(read.ok()) << read.status().message();
  ExpectSameModel(model, *read);
  EXPECT_EQ(read_info.format_version, 4u);
  EXPECT_EQ(read_info.file_bytes, file.size());
  ASSERT_EQ(read_info.parts.size(), 2u);
  EXPECT_TRUE(read_info.parts[1].quantization.lossless());
  // Deterministic: the same bytes again.
  EXPECT_EQ(Serialize(model), file);
}

TEST(SdcbModelFileTest, VersionFourBytesAreTheDocumentsLayout) {
  const Model model = TwoPartModel();
  EXPECT_EQ(Serialize(model), Join4(ExpectedChunks(model)));
}

TEST(SdcbModelFileTest, QuantizedPartsRoundTripWithTheirStorage) {
  Model model = TwoPartModel();
  model.parts[0].spline = testing::MakeGridTestModel(2, 9, 16, 3);
  model.parts[1].spline = testing::MakeGridTestModel(1, 8, 12, 5);
  SdcbWriteOptions o;
  o.quantize_bits = 12;
  SdcbFileInfo info;
  const std::string file = Serialize(model, o, &info);
  SdcbFileInfo read_info;
  const StatusOr<Model> read = ParseSdcbModel(file, &read_info);
  ASSERT_TRUE(read.ok()) << read.status().message();
  ASSERT_EQ(read_info.parts.size(), 2u);
  EXPECT_EQ(read_info.parts[0].knot_grid_bits, 16);
  EXPECT_EQ(read_info.parts[0].quantization.bits, 12);
  EXPECT_EQ(read_info.parts[1].knot_grid_bits, 12);
  EXPECT_EQ(read_info.parts[1].quantization.bits, 12);
  EXPECT_EQ(read_info.knot_grid_bits, 16);
  // The trims and names are exact whatever the control points' storage.
  EXPECT_EQ(read->parts[1].name, model.parts[1].name);
  EXPECT_TRUE(
      SameBits(read->parts[1].trims[1].points, model.parts[1].trims[1].points));
}

TEST(SdcbModelFileTest, OneClosedUnnamedPartIsWrittenAsBefore) {
  const SplineModel spline = testing::MakeTestModel(2, 8, 4);
  Model model;
  model.parts.emplace_back();
  model.parts[0].spline = spline;
  model.source = spline.source;
  SdcbWriteOptions quantized3, quantized2;
  quantized3.quantize_bits = 14;
  quantized2.quantize_bits = 14;
  quantized2.format_version = 2;
  for (const SdcbWriteOptions& o :
       {SdcbWriteOptions{}, quantized3, quantized2}) {
    const StatusOr<std::string> expected = SerializeSdcb(spline, o);
    ASSERT_TRUE(expected.ok());
    EXPECT_EQ(Serialize(model, o), *expected);
  }
  const SplineModel grid = testing::MakeGridTestModel(1, 8, 16);
  model.parts[0].spline = grid;
  model.source = grid.source;
  EXPECT_EQ(Serialize(model), *SerializeSdcb(grid));
  // A name, a trim or a model source of its own need version 4.
  Model named = model;
  named.parts[0].name = "x";
  EXPECT_EQ(testing::GetLe(Serialize(named), 8, 4), 4u);
  Model trimmed = model;
  trimmed.parts[0].trims = {CircleLoop({0, 1, 0}, 1.0, 4)};
  EXPECT_EQ(testing::GetLe(Serialize(trimmed), 8, 4), 4u);
  Model other_source = model;
  other_source.source.num_faces += 2;
  EXPECT_EQ(testing::GetLe(Serialize(other_source), 8, 4), 4u);
}

TEST(SdcbModelFileTest, EveryOlderFileReadsAsOnePart) {
  std::vector<std::filesystem::path> files = {
      testing::TestDataPath("cow_round0_v1.sdcb")};
  for (const auto& entry : std::filesystem::directory_iterator(
           std::filesystem::path(SDCB_SOURCE_DIR) / "fuzz/corpus/sdcb")) {
    std::ifstream in(entry.path(), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)),
                      std::istreambuf_iterator<char>());
    if (testing::GetLe(bytes, 8, 4) < 4) files.push_back(entry.path());
  }
  ASSERT_GE(files.size(), 10u);
  for (const auto& path : files) {
    SdcbFileInfo spline_info, model_info;
    const StatusOr<SplineModel> spline = ReadSdcbFile(path, &spline_info);
    ASSERT_TRUE(spline.ok()) << spline.status().message();
    const StatusOr<Model> model = ReadSdcbModelFile(path, &model_info);
    ASSERT_TRUE(model.ok()) << model.status().message();
    ASSERT_EQ(model->parts.size(), 1u) << path;
    EXPECT_TRUE(model->parts[0].name.empty());
    EXPECT_FALSE(model->parts[0].trimmed());
    EXPECT_TRUE(BitIdentical(model->parts[0].spline, *spline)) << path;
    EXPECT_EQ(model->source.hash, spline->source.hash);
    EXPECT_EQ(model->source.file_name, spline->source.file_name);
    EXPECT_EQ(model_info.format_version, spline_info.format_version);
    EXPECT_LE(model_info.format_version, 3u);
    EXPECT_EQ(model_info.parts.size(), 1u);
  }
}

TEST(SdcbModelFileTest, TheSplineReaderRefusesPartsAndTrims) {
  const std::string two = Serialize(TwoPartModel());
  const StatusOr<SplineModel> a = ParseSdcb(two);
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(a.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(a.status().message().find("holds 2 parts;"), std::string::npos)
      << a.status().message();
  Model one = TwoPartModel();
  one.parts.erase(one.parts.begin());
  const StatusOr<SplineModel> b = ParseSdcb(Serialize(one));
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(b.status().message().find("a trimmed part"), std::string::npos);
  // One named closed part reads as its spline.
  one.parts[0].trims.clear();
  const StatusOr<SplineModel> c = ParseSdcb(Serialize(one));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_TRUE(BitIdentical(*c, one.parts[0].spline));
}

TEST(SdcbModelFileTest, InvalidModelsAreNotWritten) {
  const auto expect_refused = [](const Model& m, const std::string& fragment) {
    const StatusOr<std::string> bytes = SerializeSdcbModel(m);
    ASSERT_FALSE(bytes.ok());
    EXPECT_EQ(bytes.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(bytes.status().message().find(fragment), std::string::npos)
        << bytes.status().message();
  };
  expect_refused(Model{}, "no parts");
  Model m = TwoPartModel();
  m.parts[1].name = "bad \xff name";
  expect_refused(m, "part 2: its name is not UTF-8");
  m.parts[1].name = std::string(kMaxPartNameBytes + 1, 'a');
  expect_refused(m, "part 2: its name has 1025 bytes");
  m = TwoPartModel();
  m.parts[1].trims[1].points.conservativeResize(2, 3);
  expect_refused(m, "part 2: trim loop 2: it has 2 points");
  m = TwoPartModel();
  m.parts[1].trims[0].points(2, 0) *= 1.001;
  expect_refused(m, "part 2: trim loop 1: point 3 is not a finite unit");
  m = TwoPartModel();
  m.parts[1].trims[0].points.row(1) = -m.parts[1].trims[0].points.row(0);
  expect_refused(m, "part 2: trim loop 1: points 1 and 2 are equal or");
  m = TwoPartModel();
  m.parts[0].spline.transform.scale = -1;
  expect_refused(m, "part 1: cannot write an invalid model");
}

TEST(SdcbModelFileTest, TruncationsAndByteFlipsAreRefused) {
  const std::string file = Serialize(TwoPartModel());
  for (size_t n = 0; n < file.size(); ++n) {
    const StatusOr<Model> m = ParseSdcbModel(file.substr(0, n));
    ASSERT_FALSE(m.ok()) << n;
    EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile) << n;
    EXPECT_FALSE(m.status().message().empty());
  }
  // Every bit and byte flip (CRC-32 catches each). The version field is not
  // covered by a CRC: a flip there is refused as another version.
  size_t largest = 0;
  for (size_t i = 0; i < file.size(); ++i) {
    for (int mask : {1, 4, 32, 128, 255}) {
      std::string bad = file;
      bad[i] = static_cast<char>(bad[i] ^ mask);
      StatusOr<Model> m = InternalError("not parsed");
      largest = std::max(largest, testing::LargestAllocationDuring(
                                      [&] { m = ParseSdcbModel(bad); }));
      ASSERT_FALSE(m.ok()) << "byte " << i << " mask " << mask;
      EXPECT_TRUE(m.status().code() == StatusCode::kCorruptFile ||
                  m.status().code() == StatusCode::kUnsupported)
          << m.status().message();
      EXPECT_FALSE(m.status().message().empty());
    }
  }
  EXPECT_LE(largest, 16 * file.size() + 4096);
}

TEST(SdcbModelFileTest, CraftedVersionFourFilesNameTheProblem) {
  const Model model = TwoPartModel();
  const std::vector<RawChunk> good = ExpectedChunks(model);
  ASSERT_TRUE(ParseSdcbModel(Join4(good)).ok());
  auto with = [&](size_t index, const RawChunk& chunk) {
    std::vector<RawChunk> c = good;
    c[index] = chunk;
    return Join4(c);
  };
  // HEAD: size and count (the count is only compared, never allocated).
  ExpectCorruptModel(with(0, {"HEAD", Le(2, 4)}), "HEAD chunk has 4 bytes");
  ExpectCorruptModel(with(0, {"HEAD", Le(0, 8)}), "HEAD declares 0 parts");
  ExpectCorruptModel(with(0, {"HEAD", Le(3, 8)}),
                     "HEAD declares 3 parts but the file has 2 PART chunks");
  ExpectCorruptModel(with(0, {"HEAD", Le(uint64_t{1} << 62, 8)}),
                     "PART chunks");
  {
    std::vector<RawChunk> c = good;
    c.erase(c.begin() + 1);
    ExpectCorruptModel(Join4(c), "the required chunk 'SRCM' is missing");
  }
  // Inside a part: messages name the part.
  const auto part = [&](const std::vector<RawChunk>& inner) {
    return with(3, {"PART", Sequence(inner)});
  };
  std::vector<RawChunk> inner =
      SplitFile(testing::JoinFile({}, 0) + good[3].payload);  // part 2's chunks
  ASSERT_EQ(inner.back().type, "END ");
  RawChunk* trim = testing::Find(inner, "TRIM");
  ASSERT_NE(trim, nullptr);
  const std::string trim_bytes = trim->payload;
  const std::string packed = trim_bytes.substr(24);  // after L = 2, 5, 7
  auto with_trim = [&](const std::string& payload) {
    std::vector<RawChunk> c = inner;
    testing::Find(c, "TRIM")->payload = payload;
    return part(c);
  };
  ExpectCorruptModel(with_trim(Le(0, 8)), "part 2: the TRIM chunk declares no");
  ExpectCorruptModel(with_trim(""), "part 2: the TRIM chunk declares no loops");
  ExpectCorruptModel(with_trim(Le(uint64_t{1} << 60, 8) + Le(5, 8)),
                     "part 2: the TRIM chunk declares 1152921504606846976 "
                     "loops, more than its 16 bytes can hold");
  ExpectCorruptModel(
      with_trim(Le(2, 8) + Le(5, 8) + Le(uint64_t{1} << 40, 8) + packed),
      "part 2: the TRIM chunk declares more points than");
  ExpectCorruptModel(with_trim(Le(2, 8) + Le(2, 8) + Le(10, 8) + packed),
                     "a loop of 2 points");
  ExpectCorruptModel(with_trim(Le(2, 8) + Le(4, 8) + Le(7, 8) + packed),
                     "part 2: the TRIM chunk declares 288 inflated bytes; the "
                     "declared counts need 264");
  {
    TrimLoop off_sphere = model.parts[1].trims[0];
    off_sphere.points(1, 2) = 2;
    ExpectCorruptModel(
        with_trim(TrimBytes({model.parts[1].trims[1], off_sphere})),
        "part 2: trim loop 2: point 2 is not a finite unit vector");
  }
  auto with_name = [&](const std::string& name) {
    std::vector<RawChunk> c = inner;
    testing::Find(c, "NAME")->payload = name;
    return part(c);
  };
  ExpectCorruptModel(with_name(""), "part 2: the NAME chunk is empty");
  ExpectCorruptModel(with_name("a\xc0\xaf"),
                     "part 2: its name is not UTF-8: the UTF-8 sequence at "
                     "byte 1 is invalid");
  ExpectCorruptModel(with_name(std::string(2000, 'n')),
                     "part 2: its name has 2000 bytes");
  {
    std::vector<RawChunk> c = inner;
    c.erase(c.begin() + (testing::Find(c, "XFRM") - c.data()));
    ExpectCorruptModel(part(c), "part 2: the required chunk 'XFRM'");
  }
  {
    // A part's inner chunk with a bad CRC, under a correct PART CRC.
    std::string payload = good[3].payload;
    payload[20] ^= 1;
    ExpectCorruptModel(with(3, {"PART", payload}),
                       "part 2: chunk 'HEAD' at byte");
    ExpectCorruptModel(with(3, {"PART", good[3].payload.substr(0, 100)}),
                       "remain (truncated or corrupt)");
    ExpectCorruptModel(with(3, {"PART", good[3].payload + "x"}),
                       "part 2: 1 unexpected bytes follow the END chunk");
  }
}

TEST(SdcbModelFileTest, AbsurdTrimCountsAllocateNothingLarge) {
  const Model model = TwoPartModel();
  const std::vector<RawChunk> good = ExpectedChunks(model);
  std::vector<RawChunk> inner =
      SplitFile(testing::JoinFile({}, 0) + good[3].payload);
  for (const std::string& trim :
       {Le(uint64_t{1} << 60, 8) + Le(5, 8),
        Le(1, 8) + Le(0x7fffffff, 8) + Le(uint64_t{1} << 40, 8),
        Le(2, 8) + Le(0x7ffffffe, 8) + Le(0x7ffffffe, 8)}) {
    testing::Find(inner, "TRIM")->payload = trim;
    std::vector<RawChunk> c = good;
    c[3].payload = Sequence(inner);
    const std::string file = Join4(c);
    StatusOr<Model> m = InternalError("not parsed");
    const size_t largest =
        testing::LargestAllocationDuring([&] { m = ParseSdcbModel(file); });
    ASSERT_FALSE(m.ok());
    EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile);
    EXPECT_LE(largest, 16 * file.size() + 4096) << m.status().message();
  }
}

// Bytes changed, inserted or dropped inside a part's chunks, every CRC
// recomputed: refused with a message, or a valid model that writes and
// reads back to itself.
TEST(SdcbModelFileTest, MutationsInsidePartsWithValidCrcsNeverCrash) {
  const std::vector<RawChunk> good = ExpectedChunks(TwoPartModel());
  std::mt19937 rng(54);
  int accepted = 0;
  for (int trial = 0; trial < 600; ++trial) {
    std::vector<RawChunk> c = good;
    const size_t which = 2 + rng() % 2;
    std::vector<RawChunk> inner =
        SplitFile(testing::JoinFile({}, 0) + c[which].payload);
    RawChunk& target = inner[rng() % (inner.size() - 1)];
    testing::MutateBytes(&rng, &target.payload);
    c[which].payload = Sequence(inner);
    const StatusOr<Model> m = ParseSdcbModel(Join4(c));
    if (!m.ok()) {
      EXPECT_TRUE(m.status().code() == StatusCode::kCorruptFile ||
                  m.status().code() == StatusCode::kUnsupported)
          << m.status().message();
      EXPECT_EQ(m.status().message().rfind("part ", 0), 0u)
          << m.status().message();
      continue;
    }
    ++accepted;
    const StatusOr<std::string> again = SerializeSdcbModel(*m);
    ASSERT_TRUE(again.ok()) << again.status().message();
    const StatusOr<Model> reread = ParseSdcbModel(*again);
    ASSERT_TRUE(reread.ok()) << reread.status().message();
    ExpectSameModel(*m, *reread);
  }
  EXPECT_LT(accepted, 600);
}

// A fitted part, then two kept parts: one of doubles no float holds (a -0.0
// among them; triangles meshoptimizer's index codec rotates), one of floats.
Model KeptPartsModel() {
  Model m = TwoPartModel();
  m.parts.resize(3);
  m.parts[1] = ModelPart();
  m.parts[1].name = "bracket";
  KeptMesh soup;
  soup.mesh.vertices.resize(9, 3);
  for (int i = 0; i < 9; ++i) {
    soup.mesh.vertices.row(i) << 0.1 * i, std::sqrt(2.0 + i), -1.0 / (3 + i);
  }
  soup.mesh.vertices(4, 1) = -0.0;
  soup.mesh.faces.resize(5, 3);
  soup.mesh.faces << 0, 1, 2, 2, 1, 3, 3, 4, 2, 5, 6, 7, 1, 0, 8;
  soup.reason =
      "part 2 (5 triangles) is not manifold; sdcb fits manifold parts";
  m.parts[1].kept = soup;
  KeptMesh tetra;
  tetra.mesh.vertices.resize(4, 3);
  tetra.mesh.vertices << 0, 0, 0, 1.5, 0, 0, 0, 0.25, 0, 0, 0, -3;
  tetra.mesh.faces.resize(4, 3);
  tetra.mesh.faces << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  tetra.reason = "part 3: the fit failed";
  m.parts[2].kept = tetra;
  return m;
}

// The kept part's documented bytes decoded by hand with meshoptimizer's
// decoders (docs/FORMAT.md, "Kept parts").
TriangleMesh DecodeKeptByHand(const std::string& part_payload) {
  std::vector<RawChunk> chunks =
      SplitFile(std::string(12, '\0') + part_payload);
  EXPECT_EQ(chunks.back().type, "END ");
  const RawChunk* head = testing::Find(chunks, "HEAD");
  const RawChunk* kept = testing::Find(chunks, "KEPT");
  EXPECT_TRUE(head != nullptr && kept != nullptr);
  EXPECT_EQ(head->payload.size(), 20u);
  const uint64_t nv = testing::GetLe(head->payload, 0, 8);
  const uint64_t nf = testing::GetLe(head->payload, 8, 8);
  const uint64_t form = testing::GetLe(head->payload, 16, 4);
  const size_t width = form == 1 ? 4 : 8, size = 3 * width;
  const std::string& k = kept->payload;
  const uint64_t vbytes = testing::GetLe(k, 0, 8);
  std::vector<unsigned char> v(nv * size);
  EXPECT_EQ(meshopt_decodeVertexBuffer(
                v.data(), nv, size,
                reinterpret_cast<const unsigned char*>(k.data() + 8), vbytes),
            0);
  const uint64_t ibytes = testing::GetLe(k, 8 + vbytes, 8);
  std::vector<unsigned int> idx(3 * nf);
  EXPECT_EQ(meshopt_decodeIndexBuffer(
                idx.data(), idx.size(), 4,
                reinterpret_cast<const unsigned char*>(k.data() + 16 + vbytes),
                ibytes),
            0);
  const std::string rotations =
      testing::TestInflate(k.substr(16 + vbytes + ibytes));
  EXPECT_EQ(rotations.size(), nf);
  TriangleMesh mesh;
  mesh.vertices.resize(nv, 3);
  for (uint64_t i = 0; i < 3 * nv; ++i) {
    double x;
    if (width == 4) {
      float f;
      std::memcpy(&f, v.data() + 4 * i, 4);
      x = f;
    } else {
      std::memcpy(&x, v.data() + 8 * i, 8);
    }
    mesh.vertices(i / 3, i % 3) = x;
  }
  mesh.faces.resize(nf, 3);
  for (uint64_t f = 0; f < nf; ++f) {
    for (int c = 0; c < 3; ++c) {
      mesh.faces(f, c) = idx[3 * f + (rotations[f] + c) % 3];
    }
  }
  return mesh;
}

TEST(SdcbModelFileTest, KeptPartsRoundTripExactly) {
  const Model m = KeptPartsModel();
  const std::string file = Serialize(m);
  StatusOr<Model> back = ParseSdcbModel(file);
  ASSERT_TRUE(back.ok()) << back.status().message();
  ExpectSameModel(m, *back);
  for (size_t i = 1; i < 3; ++i) {
    ASSERT_TRUE(back->parts[i].kept.has_value()) << i;
    EXPECT_EQ(back->parts[i].kept->reason, m.parts[i].kept->reason);
    EXPECT_TRUE(SameBits(back->parts[i].kept->mesh.vertices,
                         m.parts[i].kept->mesh.vertices));
    EXPECT_EQ(back->parts[i].kept->mesh.faces, m.parts[i].kept->mesh.faces);
  }
  EXPECT_FALSE(back->parts[0].kept.has_value());
  // The layout: version 4, a PART per part; a kept part's HEAD declares
  // its counts and the position form (0: doubles, 1: floats), and its
  // streams decode with meshoptimizer to the input.
  std::vector<RawChunk> chunks = SplitFile(file);
  std::vector<std::string> parts;
  for (const RawChunk& c : chunks) {
    if (c.type == "PART") parts.push_back(c.payload);
  }
  ASSERT_EQ(parts.size(), 3u);
  EXPECT_EQ(PartBytes(m.parts[0]), parts[0]);
  for (size_t i = 1; i < 3; ++i) {
    const TriangleMesh hand = DecodeKeptByHand(parts[i]);
    EXPECT_TRUE(SameBits(hand.vertices, m.parts[i].kept->mesh.vertices)) << i;
    EXPECT_EQ(hand.faces, m.parts[i].kept->mesh.faces) << i;
    std::vector<RawChunk> sub = SplitFile(std::string(12, '\0') + parts[i]);
    EXPECT_EQ(testing::GetLe(sub[0].payload, 16, 4), i == 1 ? 0u : 1u);
    ASSERT_NE(testing::Find(sub, "WHY "), nullptr);
    EXPECT_EQ(testing::Find(sub, "WHY ")->payload, m.parts[i].kept->reason);
  }
  // The one-spline reader refuses a kept part.
  Model one;
  one.parts = {m.parts[2]};
  one.source = m.source;
  const StatusOr<SplineModel> spline = ParseSdcb(Serialize(one));
  ASSERT_FALSE(spline.ok());
  EXPECT_EQ(spline.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(spline.status().message().find("a kept (unfitted) part"),
            std::string::npos)
      << spline.status().message();
}

TEST(SdcbModelFileTest, DamagedKeptPartsAreRefused) {
  const std::string file = Serialize(KeptPartsModel());
  for (size_t n = 0; n < file.size(); n += 7) {
    const StatusOr<Model> m = ParseSdcbModel(file.substr(0, n));
    ASSERT_FALSE(m.ok()) << n;
    EXPECT_EQ(m.status().code(), StatusCode::kCorruptFile) << n;
  }
  for (size_t i = 12; i < file.size(); ++i) {
    std::string bad = file;
    bad[i] = static_cast<char>(bad[i] ^ 16);
    ASSERT_FALSE(ParseSdcbModel(bad).ok()) << i;
  }
  // Valid CRCs around bad contents: counts that disagree with the streams,
  // an unknown position form, an absurd vertex count.
  const auto with_kept_head = [&](const std::string& head) {
    std::vector<RawChunk> chunks = SplitFile(file);
    RawChunk* part = nullptr;
    int seen = 0;
    for (RawChunk& c : chunks) {
      if (c.type == "PART" && ++seen == 3) part = &c;
    }
    std::vector<RawChunk> sub =
        SplitFile(std::string(12, '\0') + part->payload);
    sub[0].payload = head;
    part->payload = Sequence(sub);
    return Join4(chunks);
  };
  ExpectCorruptModel(with_kept_head(Le(3, 8) + Le(4, 8) + Le(1, 4)), "KEPT");
  ExpectCorruptModel(with_kept_head(Le(4, 8) + Le(4, 8) + Le(2, 4)),
                     "position form 2");
  ExpectCorruptModel(
      with_kept_head(Le(uint64_t{1} << 40, 8) + Le(4, 8) + Le(1, 4)),
      "vertices, more than the file's");
  ExpectCorruptModel(with_kept_head(Le(4, 8) + Le(5, 8) + Le(1, 4)), "KEPT");
}

TEST(SdcbModelFileTest, FilesAreWrittenAtomicallyAndReadBack) {
  const std::string dir = testing::FreshTestDir();
  const std::string path = dir + "/two.sdcb";
  ASSERT_TRUE(WriteSdcbModelFile(TwoPartModel(), path).ok());
  const StatusOr<Model> read = ReadSdcbModelFile(path);
  ASSERT_TRUE(read.ok()) << read.status().message();
  ExpectSameModel(TwoPartModel(), *read);
  Model bad = TwoPartModel();
  bad.parts[0].name = "\xff";
  const Status s = WriteSdcbModelFile(bad, dir + "/bad.sdcb");
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message().rfind(dir + "/bad.sdcb: ", 0), 0u);
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.sdcb"));
  const StatusOr<Model> missing = ReadSdcbModelFile(dir + "/none.sdcb");
  EXPECT_EQ(missing.status().code(), StatusCode::kIoError);
}

}  // namespace
}  // namespace sdcb
