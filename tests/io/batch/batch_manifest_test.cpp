// The manifest of `sdcb batch`: fields, quotes, comments, errors.
#include "sdcb/io/batch/batch_manifest.h"

#include <gtest/gtest.h>

namespace sdcb {
namespace {

using Strings = std::vector<std::string>;

TEST(BatchManifestTest, FieldsQuotesAndComments) {
  const auto rows = ParseBatchManifest(
      "# header comment\n"
      "\n"
      "a.off\tout/a.sdcb  --rmse 0.1 --degree=3   # trailing\r\n"
      "   \t  \n"
      "\"my scan.ply\" \"out/my \\\"scan\\\".glb\" --draco\n"
      "b#c.off out#1.sdcb\n"
      "\"\" x.sdcb");  // no final newline; an empty quoted field
  ASSERT_TRUE(rows.ok()) << rows.status().message();
  ASSERT_EQ(rows->size(), 4u);
  EXPECT_EQ((*rows)[0].line, 3);
  EXPECT_EQ((*rows)[0].input, "a.off");
  EXPECT_EQ((*rows)[0].output, "out/a.sdcb");
  EXPECT_EQ((*rows)[0].options, (Strings{"--rmse", "0.1", "--degree=3"}));
  EXPECT_EQ((*rows)[1].line, 5);
  EXPECT_EQ((*rows)[1].input, "my scan.ply");
  EXPECT_EQ((*rows)[1].output, "out/my \"scan\".glb");
  EXPECT_EQ((*rows)[1].options, (Strings{"--draco"}));
  // '#' inside a field is part of it; only at a field's start is it a
  // comment.
  EXPECT_EQ((*rows)[2].input, "b#c.off");
  EXPECT_EQ((*rows)[2].output, "out#1.sdcb");
  EXPECT_EQ((*rows)[3].line, 7);
  EXPECT_EQ((*rows)[3].input, "");
}

TEST(BatchManifestTest, MalformedLinesNameTheLine) {
  const struct {
    const char* text;
    const char* message;
  } cases[] = {
      {"a.off b.sdcb\nonly-one-field\n", "line 2: a row needs INPUT"},
      {"\n\"a.off b.sdcb\n", "line 2: unterminated quote"},
      {"\"a.off\"b.sdcb\n", "line 1: a closing quote"},
  };
  for (const auto& c : cases) {
    const auto rows = ParseBatchManifest(c.text);
    ASSERT_FALSE(rows.ok()) << c.text;
    EXPECT_EQ(rows.status().code(), StatusCode::kCorruptFile);
    EXPECT_NE(rows.status().message().find(c.message), std::string::npos)
        << rows.status().message();
  }
  const std::string with_nul("a.off b.sdcb\n\0\n", 15);
  EXPECT_FALSE(ParseBatchManifest(with_nul).ok());
  const auto empty = ParseBatchManifest("");
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty->empty());
}

}  // namespace
}  // namespace sdcb
