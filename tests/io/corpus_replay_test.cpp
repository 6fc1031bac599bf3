// Replays the fuzzers' corpora (fuzz/corpus/TARGET, with the regression
// inputs of past findings) and the malformed corpus (tests/data/malformed)
// through the readers in-process, so that the regular and the sanitizer
// builds of the test suite run them too. Every input is also read as every
// other mesh format. Oracles: the seeds are valid files and must be
// accepted; whatever is accepted must be a well-formed mesh (finite
// coordinates, indices in range); nothing may crash.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "sdcb/core/spline/spherical_spline.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "sdcb/io/sdcb/sdcb_file.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

namespace fs = std::filesystem;

const std::map<std::string, MeshFileFormat> kFormats = {
    {".off", MeshFileFormat::kOff},
    {".obj", MeshFileFormat::kObj},
    {".ply", MeshFileFormat::kPly},
    {".stl", MeshFileFormat::kStl}};

std::vector<fs::path> FilesIn(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file()) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

void ExpectWellFormed(const StatusOr<TriangleMesh>& mesh) {
  if (!mesh.ok()) {
    EXPECT_FALSE(mesh.status().message().empty());
    EXPECT_EQ(mesh.status().message().find('\n'), std::string::npos);
    return;
  }
  EXPECT_GT(mesh->num_faces(), 0);
  EXPECT_TRUE(mesh->vertices.allFinite());
  if (mesh->num_faces() > 0) {
    EXPECT_GE(mesh->faces.minCoeff(), 0);
    EXPECT_LT(mesh->faces.maxCoeff(), mesh->num_vertices());
  }
}

TEST(CorpusReplayTest, MeshCorporaReadOrFailCleanly) {
  const fs::path root(SDCB_SOURCE_DIR);
  int files = 0;
  for (const char* target : {"off", "obj", "ply", "stl"}) {
    for (const fs::path& path : FilesIn(root / "fuzz" / "corpus" / target)) {
      SCOPED_TRACE(path.string());
      const std::string bytes = testing::ReadBytes(path.string());
      const MeshFileFormat own = kFormats.at(path.extension().string());
      const bool regression =
          path.filename().string().rfind("regression-", 0) == 0;
      const StatusOr<TriangleMesh> mesh = ReadMeshFromBuffer(bytes, own);
      if (!regression) {
        EXPECT_TRUE(mesh.ok())
            << "a seed is a valid file: " << mesh.status().message();
      }
      for (const auto& [ext, format] : kFormats) {
        ExpectWellFormed(ReadMeshFromBuffer(bytes, format));
      }
      ++files;
    }
  }
  for (const fs::path& path : FilesIn(root / "tests" / "data" / "malformed")) {
    SCOPED_TRACE(path.string());
    const std::string bytes = testing::ReadBytes(path.string());
    for (const auto& [ext, format] : kFormats) {
      ExpectWellFormed(ReadMeshFromBuffer(bytes, format));
    }
    ++files;
  }
  EXPECT_GE(files, 80);
}

TEST(CorpusReplayTest, ModelCorpusParsesAndEvaluatesOrFailsCleanly) {
  const fs::path root(SDCB_SOURCE_DIR);
  std::vector<fs::path> files = FilesIn(root / "fuzz" / "corpus" / "sdcb");
  for (const fs::path& path : FilesIn(root / "tests" / "data" / "malformed")) {
    if (path.extension() == ".sdcb") files.push_back(path);
  }
  ASSERT_GE(files.size(), 10u);
  for (const fs::path& path : files) {
    SCOPED_TRACE(path.string());
    const std::string bytes = testing::ReadBytes(path.string());
    const StatusOr<Model> model = ParseSdcbModel(bytes);
    // Seeds are valid files; those made by `sdcb fit` (fit_*) also give a
    // surface (the fixture's random knots may leave holes in the basis).
    const std::string name = path.filename().string();
    const bool seed = path.parent_path().filename() == "sdcb" &&
                      name.rfind("regression-", 0) != 0;
    if (seed) {
      ASSERT_TRUE(model.ok()) << model.status().message();
    }
    if (!model.ok()) continue;
    for (const ModelPart& part : model->parts) {
      if (part.kept) {  // a mesh, not a surface: valid as a kept part
        EXPECT_TRUE(ValidateModelPart(part).ok());
        continue;
      }
      const StatusOr<SphericalSpline> surface = SurfaceFromModel(part.spline);
      if (seed && name.rfind("fit_", 0) == 0) {
        ASSERT_TRUE(surface.ok()) << surface.status().message();
      }
      if (!surface.ok()) continue;
      // Two evaluation paths agree to the rounding of a convex combination
      // of the control points.
      const Eigen::Vector3d p = Eigen::Vector3d(1, 2, 3).normalized();
      const Eigen::Vector3d a = surface->Evaluate(p);
      const Eigen::Vector3d b = surface->EvaluateDifferential(p).position;
      if (a.allFinite() && b.allFinite()) {
        EXPECT_LE((a - b).cwiseAbs().maxCoeff(),
                  1e-9 * part.spline.control_points.cwiseAbs().maxCoeff());
      }
    }
  }
}

}  // namespace
}  // namespace sdcb
