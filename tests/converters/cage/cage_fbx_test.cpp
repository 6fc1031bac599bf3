// Tests of converters/cage/cage_fbx: the kept cube's cage written as binary FBX
// and read back by a test-side reader (testing/fbx_binary_reader.h, no code
// shared with the writer): its vertices, faces, edges and crease layer,
// the creases compared with the cube's edges found from the geometry
// alone, the positions with the OBJ's. Blender's own import of the file is
// scripts/blender_crease_check.sh.
#include "sdcb/converters/cage/cage_fbx.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "sdcb/core/cage/sphere_cage_topology.h"
#include "testing/fbx_binary_reader.h"
#include "testing/kept_cube.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::FbxDocument;
using testing::FbxNode;
using Edge = std::pair<int, int>;

Edge MakeEdge(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// What a reader makes of the file's mesh.
struct ReadCage {
  std::vector<double> coordinates;      // 3 per vertex
  std::vector<std::vector<int>> faces;  // vertex indices
  std::vector<Edge> edges;              // in the file's Edges order
  const FbxNode* crease_layer = nullptr;
};

const FbxNode& Child(const FbxNode& node, const std::string& name) {
  const FbxNode* c = node.Find(name);
  if (c == nullptr) throw std::runtime_error(node.name + " has no " + name);
  return *c;
}

ReadCage ReadMesh(const FbxDocument& doc) {
  const FbxNode& objects = Child(doc.root, "Objects");
  const FbxNode& geometry = Child(objects, "Geometry");
  ReadCage cage;
  cage.coordinates = Child(geometry, "Vertices").properties.at(0).numbers;
  // PolygonVertexIndex: a negative entry -(i + 1) ends a face at vertex i.
  const std::vector<int64_t>& corners =
      Child(geometry, "PolygonVertexIndex").properties.at(0).integers;
  std::vector<int> face_of(corners.size()), first_of_face;
  std::vector<int> face;
  for (size_t c = 0; c < corners.size(); ++c) {
    if (face.empty()) first_of_face.push_back(static_cast<int>(c));
    face_of[c] = static_cast<int>(cage.faces.size());
    const int64_t v = corners[c];
    face.push_back(static_cast<int>(v < 0 ? -v - 1 : v));
    if (v < 0) {
      cage.faces.push_back(face);
      face.clear();
    }
  }
  // Edges: the corner an edge starts from; it ends at the face's next
  // corner (the first after the face's last).
  for (int64_t c : Child(geometry, "Edges").properties.at(0).integers) {
    const int f = face_of.at(c);
    const int k = static_cast<int>(c) - first_of_face[f];
    const auto& corners_of_f = cage.faces[f];
    cage.edges.push_back(
        MakeEdge(corners_of_f[k], corners_of_f[(k + 1) % corners_of_f.size()]));
  }
  cage.crease_layer = geometry.Find("LayerElementEdgeCrease");
  return cage;
}

// The "v x y z" lines of an OBJ, in order.
std::vector<double> ObjCoordinates(const std::string& text) {
  std::vector<double> v;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream s(line.substr(2));
    double x, y, z;
    s >> x >> y >> z;
    v.insert(v.end(), {x, y, z});
  }
  return v;
}

TEST(CageFbxTest, TheKeptCubesCageReadsBackWithItsTwelveEdgesSharp) {
  auto fit = testing::FitKeptCube();
  ASSERT_TRUE(fit.ok() && fit->features_kept);
  auto spline = SurfaceFromModel(fit->model);
  ASSERT_TRUE(spline.ok());
  auto cage_fit = FitSubdivisionCage(*spline);
  ASSERT_TRUE(cage_fit.ok()) << cage_fit.status().message();
  const SubdivisionCage& cage = cage_fit->cage;
  // In the input's frame, as the CLI writes it.
  const Eigen::MatrixX3d positions =
      fit->model.transform.ToInput(cage.vertices);
  auto bytes = CageFbxBytes(cage, positions);
  ASSERT_TRUE(bytes.ok()) << bytes.status().message();

  const FbxDocument doc = testing::ParseFbxBinary(*bytes);
  EXPECT_EQ(doc.version, 7400u);
  const ReadCage read = ReadMesh(doc);

  // 8 vertices at the OBJ's positions, to the bit.
  ASSERT_EQ(read.coordinates.size(), 24u);
  EXPECT_EQ(read.coordinates, ObjCoordinates(CageObjText(cage, positions)));
  // 6 quads.
  ASSERT_EQ(read.faces.size(), 6u);
  std::set<Edge> face_edges;
  for (const auto& f : read.faces) {
    ASSERT_EQ(f.size(), 4u);
    for (size_t k = 0; k < 4; ++k) {
      ASSERT_TRUE(f[k] >= 0 && f[k] < 8);
      face_edges.insert(MakeEdge(f[k], f[(k + 1) % 4]));
    }
  }
  // Every edge once.
  EXPECT_EQ(read.edges.size(), 12u);
  EXPECT_EQ(std::set<Edge>(read.edges.begin(), read.edges.end()), face_edges);

  // The crease layer: one value per edge, 1.0 (Blender's crease 1.0).
  ASSERT_NE(read.crease_layer, nullptr);
  const FbxNode& layer = *read.crease_layer;
  EXPECT_EQ(Child(layer, "MappingInformationType").properties.at(0).bytes,
            "ByEdge");
  EXPECT_EQ(Child(layer, "ReferenceInformationType").properties.at(0).bytes,
            "Direct");
  const std::vector<double>& crease =
      Child(layer, "EdgeCrease").properties.at(0).numbers;
  ASSERT_EQ(crease.size(), read.edges.size());
  std::set<Edge> creased;
  for (size_t e = 0; e < crease.size(); ++e) {
    EXPECT_TRUE(crease[e] == 0.0 || crease[e] == 1.0) << crease[e];
    if (crease[e] >= 0.99) creased.insert(read.edges[e]);
  }

  // The cube's edges from the geometry alone: the vertex pairs that differ
  // by the cube's side along one axis and agree along the other two.
  const auto p = [&](int i, int c) { return read.coordinates[3 * i + c]; };
  double side = 0.0;
  for (int c = 0; c < 3; ++c) {
    double lo = p(0, c), hi = p(0, c);
    for (int i = 1; i < 8; ++i) {
      lo = std::min(lo, p(i, c));
      hi = std::max(hi, p(i, c));
    }
    side = std::max(side, hi - lo);
  }
  ASSERT_GT(side, 0.0);
  std::set<Edge> cube_edges;
  for (int i = 0; i < 8; ++i) {
    for (int j = i + 1; j < 8; ++j) {
      int along = 0, same = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = std::abs(p(i, c) - p(j, c));
        if (std::abs(d - side) < 1e-3 * side) ++along;
        if (d < 1e-3 * side) ++same;
      }
      if (along == 1 && same == 2) cube_edges.insert({i, j});
    }
  }
  EXPECT_EQ(cube_edges.size(), 12u);
  EXPECT_EQ(creased, cube_edges);

  // Blender's axes and the metre (no conversion on import); the geometry
  // under the model, the model under the scene root.
  const FbxNode& settings =
      Child(Child(doc.root, "GlobalSettings"), "Properties70");
  std::map<std::string, double> values;
  for (const FbxNode& prop : settings.children) {
    const auto& v = prop.properties.at(4);
    values[prop.properties.at(0).bytes] = v.type == 'D' ? v.number : v.integer;
  }
  EXPECT_EQ(values["UpAxis"], 2);
  EXPECT_EQ(values["FrontAxisSign"], -1);
  EXPECT_EQ(values["UnitScaleFactor"], 100.0);
  const FbxNode& objects = Child(doc.root, "Objects");
  const int64_t geometry = Child(objects, "Geometry").properties.at(0).integer;
  const int64_t model = Child(objects, "Model").properties.at(0).integer;
  std::set<std::pair<int64_t, int64_t>> links;
  for (const FbxNode& c : Child(doc.root, "Connections").children) {
    links.insert({c.properties.at(1).integer, c.properties.at(2).integer});
  }
  EXPECT_EQ(links, (std::set<std::pair<int64_t, int64_t>>{{geometry, model},
                                                          {model, 0}}));
  // The same cage, the same bytes.
  EXPECT_EQ(*CageFbxBytes(cage, positions), *bytes);
}

// A cage without creases: every edge listed, no crease layer.
TEST(CageFbxTest, ACageWithoutCreasesHasNoCreaseLayer) {
  SubdivisionCage cage;
  cage.layout = SphereCageTopology::Create(CageCellShape::kQuad, 1).cage();
  cage.vertices = cage.layout.sphere_points;
  auto bytes = CageFbxBytes(cage, cage.vertices);
  ASSERT_TRUE(bytes.ok()) << bytes.status().message();
  const ReadCage read = ReadMesh(testing::ParseFbxBinary(*bytes));
  EXPECT_EQ(read.coordinates.size(), 3u * 26);
  EXPECT_EQ(read.faces.size(), 24u);
  // Euler: V - E + F = 2.
  EXPECT_EQ(read.edges.size(), 48u);
  EXPECT_EQ(std::set<Edge>(read.edges.begin(), read.edges.end()).size(), 48u);
  EXPECT_EQ(read.crease_layer, nullptr);
}

TEST(CageFbxTest, RefusesWhatFbxCannotSay) {
  SubdivisionCage quads;
  quads.layout = SphereCageTopology::Create(CageCellShape::kQuad, 0).cage();
  quads.vertices = quads.layout.sphere_points;
  // Too few positions.
  EXPECT_EQ(CageFbxBytes(quads, quads.vertices.topRows(7)).status().code(),
            StatusCode::kInvalidArgument);
  // A crease between two vertices that share no face edge (opposite
  // corners of a face).
  SubdivisionCage bad = quads;
  bad.creases.push_back({quads.layout.faces[0][0], quads.layout.faces[0][2]});
  EXPECT_EQ(CageFbxBytes(bad, bad.vertices).status().code(),
            StatusCode::kInvalidArgument);
  // A Loop cage: FBX has no Loop scheme.
  SubdivisionCage loop;
  loop.scheme = SubdivisionScheme::kLoop;
  loop.layout = SphereCageTopology::Create(CageCellShape::kTriangle, 0).cage();
  loop.vertices = loop.layout.sphere_points;
  EXPECT_EQ(CageFbxBytes(loop, loop.vertices).status().code(),
            StatusCode::kInvalidArgument);
}

TEST(CageFbxTest, AnUnwritablePathLeavesNothing) {
  const std::string dir = testing::FreshTestDir();
  SubdivisionCage cage;
  cage.layout = SphereCageTopology::Create(CageCellShape::kQuad, 0).cage();
  cage.vertices = cage.layout.sphere_points;
  const std::string path = dir + "/missing/cage.fbx";
  const Status s = WriteCageFbx(cage, cage.vertices, path);
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.message().rfind(path, 0), 0u) << s.message();
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  ASSERT_TRUE(WriteCageFbx(cage, cage.vertices, dir + "/cage.fbx").ok());
  EXPECT_EQ(testing::ReadBytes(dir + "/cage.fbx"),
            *CageFbxBytes(cage, cage.vertices));
}

}  // namespace
}  // namespace sdcb
