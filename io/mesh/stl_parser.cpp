// STL. Binary when the size is exactly 84 + 50 n for the triangle count n
// stored at byte 80 (whatever the 80-byte header says: many binary files
// start with "solid"); otherwise ascii: "solid NAME", then facets
// "facet normal a b c / outer loop / vertex x y z (3 times) / endloop /
// endfacet", then "endsolid [NAME]"; several solids may follow each other.
// STL stores no shared vertices: exactly equal positions are merged, and
// vertices are numbered in order of first appearance.
#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "sdcb/io/mesh/mesh_parsing.h"

namespace sdcb::mesh_parsing {
namespace {

// Merges corners with equal positions into one vertex.
class VertexMerger {
 public:
  explicit VertexMerger(MeshBuilder* builder) : builder_(builder) {}

  // The index of the vertex at (x, y, z), added if new. Coordinates must be
  // finite.
  StatusOr<int> Index(double x, double y, double z) {
    // + 0.0 turns -0.0 into +0.0: equal values, one key.
    const Key key = {x + 0.0, y + 0.0, z + 0.0};
    const auto [it, inserted] =
        index_.emplace(key, static_cast<int>(builder_->num_vertices()));
    if (inserted) {
      const Status added = builder_->AddVertex(x, y, z);
      if (!added.ok()) return added;
    }
    return it->second;
  }

 private:
  using Key = std::array<double, 3>;
  struct Hash {
    size_t operator()(const Key& k) const {
      uint64_t h = 0x9E3779B97F4A7C15ull;
      for (double c : k) {
        uint64_t bits;
        std::memcpy(&bits, &c, sizeof bits);
        h = (h ^ bits) * 0x100000001B3ull;
        h ^= h >> 29;
      }
      return static_cast<size_t>(h);
    }
  };
  MeshBuilder* builder_;
  std::unordered_map<Key, int, Hash> index_;
};

Status AddTriangle(const double corner[3][3], VertexMerger* merger,
                   MeshBuilder* builder) {
  int indices[3];
  for (int k = 0; k < 3; ++k) {
    SDCB_ASSIGN_OR_RETURN(
        indices[k], merger->Index(corner[k][0], corner[k][1], corner[k][2]));
  }
  return builder->AddPolygon(indices, 3);
}

Status ParseBinaryStl(std::string_view bytes, uint32_t triangles,
                      MeshBuilder* builder) {
  SDCB_RETURN_IF_ERROR(builder->Reserve(triangles / 2 + 2, triangles));
  VertexMerger merger(builder);
  for (uint32_t t = 0; t < triangles; ++t) {
    // Normal (3 floats, ignored), 3 corners (9 floats), 2 attribute bytes.
    const char* record = bytes.data() + 84 + 50 * size_t{t};
    double corner[3][3];
    for (int k = 0; k < 9; ++k) {
      float c;
      std::memcpy(&c, record + 12 + 4 * k, 4);
      if (!std::isfinite(c)) {
        return CorruptFileError("triangle " + Num(t) +
                                " has a non-finite coordinate");
      }
      corner[k / 3][k % 3] = c;
    }
    SDCB_RETURN_IF_ERROR(AddTriangle(corner, &merger, builder));
  }
  return Status::Ok();
}

// The tokens of a text, with the number of the line each came from.
class TokenStream {
 public:
  explicit TokenStream(std::string_view text) : lines_(text), tokens_({}) {}

  bool Next(std::string_view* token) {
    while (!tokens_.Next(token)) {
      std::string_view line;
      if (!lines_.Next(&line)) return false;
      tokens_ = Tokenizer(line);
    }
    return true;
  }
  // Drops the rest of the current line (a solid's name).
  void SkipLine() { tokens_ = Tokenizer({}); }
  int64_t line() const { return lines_.number(); }

 private:
  LineCursor lines_;
  Tokenizer tokens_;
};

Status ParseAsciiStl(std::string_view text, MeshBuilder* builder) {
  TokenStream in(text);
  VertexMerger merger(builder);
  const Status truncated =
      CorruptFileError("the ASCII STL is truncated (no matching 'endsolid')");
  std::string_view token;
  auto expect = [&](std::string_view word) {
    if (!in.Next(&token)) return truncated;
    if (token == word) return Status::Ok();
    return CorruptFileError("line " + Num(in.line()) + ": expected '" +
                            std::string(word) + "', found " + Quoted(token));
  };
  SDCB_RETURN_IF_ERROR(expect("solid"));
  in.SkipLine();
  for (;;) {
    if (!in.Next(&token)) return truncated;
    if (token == "endsolid") {
      in.SkipLine();
      if (!in.Next(&token)) return Status::Ok();
      // Another solid follows.
      if (token != "solid") {
        return CorruptFileError("line " + Num(in.line()) +
                                ": expected 'solid' after 'endsolid', found " +
                                Quoted(token));
      }
      in.SkipLine();
      continue;
    }
    if (token != "facet") {
      return CorruptFileError("line " + Num(in.line()) +
                              ": expected 'facet' or 'endsolid', found " +
                              Quoted(token));
    }
    if (!in.Next(&token)) return truncated;
    if (token == "normal") {
      // The normal is not needed (and some writers put "nan" there).
      for (int k = 0; k < 3; ++k) {
        if (!in.Next(&token)) return truncated;
      }
      if (!in.Next(&token)) return truncated;
    }
    if (token != "outer") {
      return CorruptFileError("line " + Num(in.line()) +
                              ": expected 'outer loop', found " +
                              Quoted(token));
    }
    SDCB_RETURN_IF_ERROR(expect("loop"));
    double corner[3][3];
    int corners = 0;
    for (;;) {
      if (!in.Next(&token)) return truncated;
      if (token == "endloop") break;
      if (token != "vertex" || corners == 3) {
        return CorruptFileError(
            "line " + Num(in.line()) +
            ": an STL facet must have exactly three vertices");
      }
      for (int k = 0; k < 3; ++k) {
        if (!in.Next(&token)) return truncated;
        if (!ParseFiniteDouble(token, &corner[corners][k])) {
          return CorruptFileError("line " + Num(in.line()) +
                                  ": malformed or non-finite STL vertex " +
                                  "coordinate " + Quoted(token));
        }
      }
      ++corners;
    }
    if (corners != 3) {
      return CorruptFileError(
          "line " + Num(in.line()) +
          ": an STL facet must have exactly three vertices");
    }
    SDCB_RETURN_IF_ERROR(expect("endfacet"));
    SDCB_RETURN_IF_ERROR(AddTriangle(corner, &merger, builder));
  }
}

}  // namespace

Status ParseStl(std::string_view bytes, const MeshReadLimits& limits,
                MeshBuilder* builder) {
  const size_t size = bytes.size();
  uint32_t declared = 0;
  if (size >= 84) std::memcpy(&declared, bytes.data() + 80, 4);
  if (size >= 84 && size == 84 + 50 * uint64_t{declared}) {
    return ParseBinaryStl(bytes, declared, builder);
  }
  const size_t first = bytes.find_first_not_of(" \t\r\n\v\f");
  const bool starts_solid =
      first != std::string_view::npos && bytes.substr(first, 5) == "solid";
  // Text has no NUL bytes; a binary STL whose header starts with "solid"
  // does, so its size mismatch is reported as such.
  const bool looks_binary =
      bytes.substr(0, 512).find('\0') != std::string_view::npos;
  if (starts_solid && !looks_binary) return ParseAsciiStl(bytes, builder);
  if (size < 84) {
    return CorruptFileError(
        "the file is " + Num(size) +
        " bytes, too short for a binary STL, and is not ASCII STL");
  }
  return CorruptFileError(
      "truncated or corrupt binary STL: the header declares " + Num(declared) +
      " triangles (" + Num(84 + 50 * int64_t{declared}) +
      " bytes), but the file has " + Num(size) + " bytes");
}

}  // namespace sdcb::mesh_parsing
