// ValidateModel on kept parts (core/spline/model.h): what a kept part must
// hold, each problem named with its part.
#include "sdcb/core/spline/model.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace sdcb {
namespace {

Model OneKeptTriangle() {
  Model m;
  m.parts.resize(1);
  KeptMesh kept;
  kept.mesh.vertices.resize(3, 3);
  kept.mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  kept.mesh.faces.resize(1, 3);
  kept.mesh.faces << 0, 1, 2;
  kept.reason = "part 1 (1 triangles) is kept";
  m.parts[0].kept = kept;
  return m;
}

void ExpectInvalid(const Model& m, const std::string& fragment) {
  const Status s = ValidateModel(m);
  ASSERT_FALSE(s.ok()) << fragment;
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message().rfind("part 1: ", 0), 0u) << s.message();
  EXPECT_NE(s.message().find(fragment), std::string::npos) << s.message();
}

TEST(ModelTest, AKeptPartHoldsTrianglesAndAReason) {
  const Model valid = OneKeptTriangle();
  EXPECT_TRUE(ValidateModel(valid).ok());
  EXPECT_FALSE(valid.parts[0].fitted());

  Model m = valid;
  m.parts[0].trims.resize(1);
  ExpectInvalid(m, "a kept part has trims");
  m = valid;
  m.parts[0].kept->mesh.faces.resize(0, 3);
  ExpectInvalid(m, "kept with no faces");
  m = valid;
  m.parts[0].kept->reason.clear();
  ExpectInvalid(m, "kept without a reason");
  m = valid;
  m.parts[0].kept->mesh.vertices(1, 2) =
      std::numeric_limits<double>::infinity();
  ExpectInvalid(m, "not finite");
  m = valid;
  m.parts[0].kept->mesh.faces(0, 2) = 3;
  ExpectInvalid(m, "refers to vertex 3");
}

}  // namespace
}  // namespace sdcb
