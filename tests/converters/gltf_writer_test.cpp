// Tests converters/gltf_writer.* and, in the same process, a Draco round
// trip: libdraco.so exports its own older tinygltf, and mixing the two copies
// crashes. This binary links both, like the sdcb executable.
#include "sdcb/converters/gltf_writer.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "sdcb/io/mesh_reader.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

TEST(GltfWriterTest, GltfAndGlbRoundTripTheBunny) {
  const std::string dir = testing::FreshTestDir();
  auto bunny = ReadMesh(testing::MeshPath("bunny00.off"));
  ASSERT_TRUE(bunny.ok()) << bunny.status().message();
  for (const char* name : {"bunny.gltf", "bunny.glb"}) {
    SCOPED_TRACE(name);
    const std::string path = dir + "/" + name;
    ASSERT_TRUE(WriteGltfMesh(*bunny, path).ok());
    auto back = ReadGltfMesh(path);
    ASSERT_TRUE(back.ok()) << back.status().message();
    EXPECT_EQ(back->faces, bunny->faces);
    ASSERT_EQ(back->num_vertices(), bunny->num_vertices());
    // Positions are stored as float32: relative error <= 2^-24.
    const double scale = bunny->vertices.cwiseAbs().maxCoeff();
    EXPECT_LE((back->vertices - bunny->vertices).cwiseAbs().maxCoeff(),
              scale * 6e-8);
  }
}

TEST(GltfWriterTest, CorruptGltfIsAStatus) {
  const std::string dir = testing::FreshTestDir();
  testing::WriteBytes(dir + "/bad.glb", "glTF\x02\x00\x00\x00garbage");
  testing::WriteBytes(dir + "/bad.gltf", "{\"asset\": ");
  EXPECT_FALSE(ReadGltfMesh(dir + "/bad.glb").ok());
  EXPECT_FALSE(ReadGltfMesh(dir + "/bad.gltf").ok());
  EXPECT_FALSE(ReadGltfMesh(dir + "/missing.glb").ok());
}

TEST(GltfWriterTest, UnwritableDestinationLeavesNothing) {
  const std::string dir = testing::FreshTestDir();
  auto cow = ReadMesh(testing::MeshPath("cow.off"));
  ASSERT_TRUE(cow.ok());
  const Status s = WriteGltfMesh(*cow, dir + "/missing_dir/cow.glb");
  EXPECT_FALSE(s.ok());
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(GltfWriterTest, DracoAndTinygltfCoexistInOneProcess) {
  const std::string dir = testing::FreshTestDir();
  auto cow = ReadMesh(testing::MeshPath("cow.off"));
  ASSERT_TRUE(cow.ok());
  // tinygltf (ours) first...
  ASSERT_TRUE(WriteGltfMesh(*cow, dir + "/cow.glb").ok());
  ASSERT_TRUE(ReadGltfMesh(dir + "/cow.glb").ok());
  // ...then Draco, then tinygltf again.
  draco::TriangleSoupMeshBuilder builder;
  builder.Start(cow->num_faces());
  const int position = builder.AddAttribute(draco::GeometryAttribute::POSITION,
                                            3, draco::DT_FLOAT32);
  for (int f = 0; f < cow->num_faces(); ++f) {
    float corner[3][3];
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) {
        corner[k][c] = static_cast<float>(cow->vertices(cow->faces(f, k), c));
      }
    }
    builder.SetAttributeValuesForFace(position, draco::FaceIndex(f), corner[0],
                                      corner[1], corner[2]);
  }
  std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
  ASSERT_NE(mesh, nullptr);
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
  draco::EncoderBuffer buffer;
  ASSERT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &buffer).ok());
  draco::DecoderBuffer in;
  in.Init(buffer.data(), buffer.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&in);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded.value()->num_faces(),
            static_cast<uint32_t>(cow->num_faces()));
  ASSERT_TRUE(WriteGltfMesh(*cow, dir + "/cow2.gltf").ok());
  EXPECT_TRUE(ReadGltfMesh(dir + "/cow2.gltf").ok());
}

}  // namespace
}  // namespace sdcb
