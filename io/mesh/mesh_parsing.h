// Internal to io/mesh/mesh_reader.cpp and the per-format parsers
// (io/{off,obj,ply,stl}_parser.cpp): the mesh under construction, with the
// limits enforced as it grows, and the text scanning every text format
// shares (lines, tokens, locale-independent numbers). Not part of the API.
#ifndef SDCB_IO_MESH_MESH_PARSING_H_
#define SDCB_IO_MESH_MESH_PARSING_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/io/mesh/mesh_reader.h"

namespace sdcb::mesh_parsing {

std::string Num(int64_t x);

// Vertices and triangulated polygons as a parser finds them. Every
// addition checks MeshReadLimits (counts and the memory estimate), so a
// parser cannot be talked into unbounded memory.
class MeshBuilder {
 public:
  MeshBuilder(const MeshReadLimits& limits, size_t input_bytes,
              int64_t bytes_per_corner = 0);

  // For formats that declare their counts: checks them against the limits
  // (triangles >= polygons) and reserves the arrays.
  Status Reserve(int64_t vertices, int64_t polygons);

  Status AddVertex(double x, double y, double z);
  // A polygon of `n` >= 3 corners (indices are the caller's to check),
  // triangulated as a fan from its first corner; Finish re-triangulates a
  // non-convex one of at most kMaxClippedCorners corners by ear clipping.
  Status AddPolygon(const int* corners, int64_t n);

  // Larger non-convex polygons keep the fan (ear clipping is cubic in n at
  // worst; polygons that large are not what mesh files hold).
  static constexpr int64_t kMaxClippedCorners = 64;

  int64_t num_vertices() const {
    return static_cast<int64_t>(coordinates_.size() / 3);
  }
  int64_t num_triangles() const {
    return static_cast<int64_t>(triangles_.size() / 3);
  }
  int64_t num_polygons() const { return polygons_; }

  // A sentence for MeshReadInfo::warnings.
  void Warn(std::string warning) { warnings_.push_back(std::move(warning)); }

  // Moves the arrays into a TriangleMesh.
  TriangleMesh Finish(MeshReadInfo* info);

 private:
  Status CheckCounts(int64_t vertices, int64_t triangles) const;
  // The estimate of MeshReadLimits::max_memory_bytes for these sizes.
  Status CheckMemory(int64_t vertices, int64_t triangles) const;
  // Replaces the fan of the polygon `corners` (n of them, its fan starting
  // at triangle `first_triangle`) by an ear-clipped triangulation when the
  // polygon is not convex in its plane; keeps the fan when a corner is not
  // a vertex yet (the caller reports that) or no ear is found (a
  // self-intersecting or degenerate polygon).
  void ClipIfNotConvex(int64_t first_triangle, const int* corners, int n);

  const MeshReadLimits& limits_;
  int64_t input_bytes_;
  int64_t bytes_per_corner_;
  std::vector<double> coordinates_;  // x y z per vertex
  std::vector<int> triangles_;       // 3 indices per triangle
  int64_t polygons_ = 0;
  int64_t triangulated_polygons_ = 0;
  std::vector<std::string> warnings_;
  // Polygons with 3 < n <= kMaxClippedCorners whose corners were not all
  // vertices yet when they came: their first fan triangle and the offset of
  // their n corners in clipped_corners_.
  struct PolygonToClip {
    int64_t first_triangle;
    int64_t first_corner;
    int64_t n;
  };
  std::vector<PolygonToClip> polygons_to_clip_;
  std::vector<int> clipped_corners_;
};

// Checks a polygon's corner count: 3 <= n <= limits.max_polygon_corners
// and, when `num_vertices` >= 0, n <= num_vertices.
Status CheckCorners(int64_t polygon, int64_t n, int64_t num_vertices,
                    const MeshReadLimits& limits);

// Splits text into lines at '\n' (a '\r' before it is whitespace, so CRLF
// files read like LF files), without copying.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  bool Next(std::string_view* line);
  int64_t number() const { return number_; }  // 1-based, of the last line
  size_t offset() const { return pos_; }      // where the next line starts

 private:
  std::string_view text_;
  size_t pos_ = 0;
  int64_t number_ = 0;
};

// The C locale's whitespace: space, \t, \v, \f, \r, \n.
inline bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r' ||
         c == '\n';
}

// Tokens of one line (or of any text) separated by whitespace.
class Tokenizer {
 public:
  explicit Tokenizer(std::string_view text) : text_(text) {}
  bool Next(std::string_view* token);
  // True if only whitespace is left.
  bool AtEnd();

 private:
  std::string_view text_;
  size_t pos_ = 0;
};

// `line` up to its first '#' (OFF and OBJ comments may start anywhere).
std::string_view WithoutComment(std::string_view line);

// A finite number in C syntax: optional sign, decimal ("1.5e-3", ".5",
// "1.") or hexadecimal ("0x1.8p3"). Values below the smallest double read
// as zero; "nan", "inf", values beyond the double range and anything with
// extra characters are refused. Independent of the C locale.
bool ParseFiniteDouble(std::string_view token, double* value);

// A decimal integer with optional sign that fits in int64_t.
bool ParseInt64(std::string_view token, int64_t* value);

// `token` quoted for a message: printable bytes as is, others as \xNN, cut
// after 40 characters.
std::string Quoted(std::string_view token);

// The parsers: each reads a complete file's bytes into `builder`.
Status ParseOff(std::string_view text, const MeshReadLimits& limits,
                MeshBuilder* builder);
Status ParseObj(std::string_view text, const MeshReadLimits& limits,
                MeshBuilder* builder);
Status ParsePly(std::string_view bytes, const MeshReadLimits& limits,
                MeshBuilder* builder);
Status ParseStl(std::string_view bytes, const MeshReadLimits& limits,
                MeshBuilder* builder);

}  // namespace sdcb::mesh_parsing

#endif  // SDCB_IO_MESH_MESH_PARSING_H_
