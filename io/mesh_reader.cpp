#include "sdcb/io/mesh_reader.h"

#include <unistd.h>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

namespace sdcb {
namespace {

namespace fs = std::filesystem;

// Upper bound on declared element counts; larger meshes are refused before
// anything is allocated.
constexpr int64_t kMaxElements = 200'000'000;
// Upper bound on the corners of one polygon.
constexpr int64_t kMaxPolygonCorners = 100'000;

std::string Num(int64_t x) { return std::to_string(x); }

// What the pre-scan learned from the file itself.
struct Declared {
  int64_t vertices = 0;
  int64_t polygons = 0;
  int64_t triangles = 0;  // sum over polygons of (corners - 2)
  // OpenMesh's OFF reader fails on comment lines (CGAL's files have them
  // before the header and between the sections); such files are handed to
  // it as a copy without comment and blank lines.
  bool has_comments = false;
  // The vertex coordinates as parsed here in double precision (x y z per
  // vertex), for the formats the scan parses (OFF, OBJ, PLY). OpenMesh's
  // readers keep only float precision; these replace its values.
  std::vector<double> coordinates;
};

// ---------------------------------------------------------------------------
// Collects OpenMesh's parse into plain arrays, without building a half-edge
// structure: a half-edge mesh cannot hold non-manifold input, and `sdcb
// check` must be able to count it.
class RawImporter : public OpenMesh::IO::BaseImporter {
 public:
  std::vector<OpenMesh::Vec3d> points;
  std::vector<std::vector<int>> polygons;

  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override {
    return add_vertex(OpenMesh::Vec3d(p[0], p[1], p[2]));
  }
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
    points.push_back(p);
    return OpenMesh::VertexHandle(static_cast<int>(points.size()) - 1);
  }
  OpenMesh::VertexHandle add_vertex() override {
    return add_vertex(OpenMesh::Vec3d(0, 0, 0));
  }
  OpenMesh::HalfedgeHandle add_edge(OpenMesh::VertexHandle,
                                    OpenMesh::VertexHandle) override {
    return OpenMesh::HalfedgeHandle();
  }
  OpenMesh::FaceHandle add_face(const VHandles& corners) override {
    std::vector<int> polygon;
    polygon.reserve(corners.size());
    for (const auto& vh : corners) polygon.push_back(vh.idx());
    polygons.push_back(std::move(polygon));
    return OpenMesh::FaceHandle(static_cast<int>(polygons.size()) - 1);
  }
  OpenMesh::FaceHandle add_face(OpenMesh::HalfedgeHandle) override {
    return OpenMesh::FaceHandle();
  }
  // Attributes are not needed.
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                          const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle,
                          const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(OpenMesh::FaceHandle, int) override {}
  void set_point(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f& p) override {
    if (vh.idx() >= 0 && vh.idx() < static_cast<int>(points.size())) {
      points[vh.idx()] = OpenMesh::Vec3d(p[0], p[1], p[2]);
    }
  }
  void set_halfedge(OpenMesh::VertexHandle, OpenMesh::HalfedgeHandle) override {
  }
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_status(OpenMesh::VertexHandle,
                  const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(OpenMesh::HalfedgeHandle, OpenMesh::HalfedgeHandle) override {}
  void set_face(OpenMesh::HalfedgeHandle, OpenMesh::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec2f&) override {
  }
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec3f&) override {
  }
  void set_status(OpenMesh::HalfedgeHandle,
                  const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::EdgeHandle,
                  const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::FaceHandle,
                  const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  size_t n_vertices() const override { return points.size(); }
  size_t n_faces() const override { return polygons.size(); }
  size_t n_edges() const override { return 0; }
};

// ---------------------------------------------------------------------------
// Text helpers for the pre-scans.

// Splits `text` into lines without copying.
class LineCursor {
 public:
  explicit LineCursor(const std::string& text) : text_(text) {}
  bool Next(std::string_view* line) {
    if (pos_ >= text_.size()) return false;
    size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    *line = std::string_view(text_).substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  int64_t number() const { return number_; }

 private:
  const std::string& text_;
  size_t pos_ = 0;
  int64_t number_ = 0;
};

std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i])))
      ++i;
    size_t j = i;
    while (j < line.size() &&
           !std::isspace(static_cast<unsigned char>(line[j])))
      ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

bool ParseInt(std::string_view token, int64_t* value) {
  std::string s(token);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || errno == ERANGE) return false;
  *value = v;
  return true;
}

// A finite decimal number; "nan", "inf" and garbage are refused.
bool ParseFinite(std::string_view token, double* value) {
  std::string s(token);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

bool IsBlankOrComment(std::string_view line) {
  for (char c : line) {
    if (c == '#') return true;
    if (!std::isspace(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

Status CheckCount(int64_t count, const char* what) {
  if (count < 0) {
    return CorruptFileError(
        std::string("the header declares a negative number of ") + what + " (" +
        Num(count) + ")");
  }
  if (count > kMaxElements) {
    return CorruptFileError(std::string("the header declares ") + Num(count) +
                            " " + what + ", more than sdcb accepts (" +
                            Num(kMaxElements) + ")");
  }
  return Status::Ok();
}

Status CheckPolygon(int64_t polygon, int64_t corners, int64_t num_vertices) {
  if (corners < 3 || corners > kMaxPolygonCorners || corners > num_vertices) {
    return CorruptFileError("face " + Num(polygon) + " declares " +
                            Num(corners) + " corners");
  }
  return Status::Ok();
}

Status CheckIndex(int64_t polygon, int64_t index, int64_t num_vertices) {
  if (index < 0 || index >= num_vertices) {
    return CorruptFileError("face " + Num(polygon) + " refers to vertex " +
                            Num(index) + ", but the file has " +
                            Num(num_vertices) + " vertices (valid: 0.." +
                            Num(num_vertices - 1) + ")");
  }
  return Status::Ok();
}

StatusOr<std::string> ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return IoError("cannot open the file for reading");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return IoError("reading the file failed");
  return buffer.str();
}

// ---------------------------------------------------------------------------
// OFF (ascii): header, counts, one vertex per line, one face per line.
StatusOr<Declared> ScanOff(const std::string& text) {
  Declared d;
  {
    LineCursor all(text);
    std::string_view any;
    while (all.Next(&any) && !d.has_comments)
      d.has_comments = IsBlankOrComment(any);
  }
  LineCursor lines(text);
  std::string_view line;
  std::vector<std::string_view> header;
  while (lines.Next(&line)) {
    if (IsBlankOrComment(line)) continue;
    header = Tokens(line);
    break;
  }
  if (header.empty()) return CorruptFileError("the file has no OFF header");
  const std::string keyword(header[0]);
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF") {
    return CorruptFileError("the first line is '" + keyword +
                            "', not an OFF header");
  }
  if (keyword.find_first_of("4n") != std::string::npos ||
      (header.size() > 1 && header[1] == "BINARY")) {
    return UnsupportedError(
        "'" + keyword +
        "' (binary or higher-dimensional OFF) is not supported");
  }
  std::vector<std::string_view> counts(header.begin() + 1, header.end());
  while (counts.empty() && lines.Next(&line)) {
    if (!IsBlankOrComment(line)) counts = Tokens(line);
  }
  if (counts.size() < 2 || !ParseInt(counts[0], &d.vertices) ||
      !ParseInt(counts[1], &d.polygons)) {
    return CorruptFileError("the OFF header has no vertex and face counts");
  }
  SDCB_RETURN_IF_ERROR(CheckCount(d.vertices, "vertices"));
  SDCB_RETURN_IF_ERROR(CheckCount(d.polygons, "faces"));
  // Each vertex line takes at least 6 bytes ("0 0 0\n"), each face 8.
  const int64_t min_bytes = 6 * d.vertices + 8 * d.polygons;
  if (min_bytes > static_cast<int64_t>(text.size())) {
    return CorruptFileError("the header declares " + Num(d.vertices) +
                            " vertices and " + Num(d.polygons) +
                            " faces, which cannot fit in " + Num(text.size()) +
                            " bytes (truncated file?)");
  }
  int64_t v = 0;
  d.coordinates.reserve(3 * d.vertices);
  while (v < d.vertices && lines.Next(&line)) {
    if (IsBlankOrComment(line)) continue;
    const auto t = Tokens(line);
    double x;
    for (int k = 0; k < 3; ++k) {
      const bool ok = k < static_cast<int>(t.size()) && ParseFinite(t[k], &x);
      if (ok) d.coordinates.push_back(x);
      if (!ok) {
        return CorruptFileError("line " + Num(lines.number()) + ": vertex " +
                                Num(v) +
                                (k < static_cast<int>(t.size())
                                     ? " has coordinate '" + std::string(t[k]) +
                                           "', which is not a finite number"
                                     : " has fewer than three coordinates"));
      }
    }
    ++v;
  }
  if (v < d.vertices) {
    return CorruptFileError("the file is truncated: it declares " +
                            Num(d.vertices) + " vertices but holds " + Num(v));
  }
  int64_t f = 0;
  while (f < d.polygons && lines.Next(&line)) {
    if (IsBlankOrComment(line)) continue;
    const auto t = Tokens(line);
    int64_t corners = 0;
    if (!ParseInt(t[0], &corners)) {
      return CorruptFileError("line " + Num(lines.number()) + ": face " +
                              Num(f) + " does not start with a corner count");
    }
    SDCB_RETURN_IF_ERROR(CheckPolygon(f, corners, d.vertices));
    if (static_cast<int64_t>(t.size()) < corners + 1) {
      return CorruptFileError("line " + Num(lines.number()) + ": face " +
                              Num(f) + " declares " + Num(corners) +
                              " corners but lists " + Num(t.size() - 1));
    }
    for (int64_t k = 1; k <= corners; ++k) {
      int64_t index;
      if (!ParseInt(t[k], &index)) {
        return CorruptFileError("line " + Num(lines.number()) + ": face " +
                                Num(f) + " has a corner '" + std::string(t[k]) +
                                "' that is not an index");
      }
      SDCB_RETURN_IF_ERROR(CheckIndex(f, index, d.vertices));
    }
    d.triangles += corners - 2;
    ++f;
  }
  if (f < d.polygons) {
    return CorruptFileError("the file is truncated: it declares " +
                            Num(d.polygons) + " faces but holds " + Num(f));
  }
  return d;
}

// ---------------------------------------------------------------------------
// OBJ: 'v' and 'f' lines; everything else is ignored.
StatusOr<Declared> ScanObj(const std::string& text) {
  Declared d;
  {
    LineCursor lines(text);
    std::string_view line;
    while (lines.Next(&line)) {
      const auto t = Tokens(line);
      if (t.empty() || t[0] != "v") continue;
      double x;
      for (int k = 1; k <= 3; ++k) {
        const bool ok = k < static_cast<int>(t.size()) && ParseFinite(t[k], &x);
        if (ok) d.coordinates.push_back(x);
        if (!ok) {
          return CorruptFileError(
              "line " + Num(lines.number()) + ": vertex " + Num(d.vertices) +
              (k < static_cast<int>(t.size())
                   ? " has coordinate '" + std::string(t[k]) +
                         "', which is not a finite number"
                   : " has fewer than three coordinates"));
        }
      }
      if (++d.vertices > kMaxElements) {
        return CorruptFileError("the file has more than " + Num(kMaxElements) +
                                " vertices");
      }
    }
  }
  LineCursor lines(text);
  std::string_view line;
  while (lines.Next(&line)) {
    const auto t = Tokens(line);
    if (t.empty() || t[0] != "f") continue;
    const int64_t corners = static_cast<int64_t>(t.size()) - 1;
    SDCB_RETURN_IF_ERROR(CheckPolygon(d.polygons, corners, d.vertices)
                             .WithPrefix("line " + Num(lines.number())));
    for (size_t k = 1; k < t.size(); ++k) {
      int64_t index;
      const std::string_view head = t[k].substr(0, t[k].find('/'));
      if (!ParseInt(head, &index)) {
        return CorruptFileError("line " + Num(lines.number()) + ": face " +
                                Num(d.polygons) + " has a corner '" +
                                std::string(t[k]) + "' that is not an index");
      }
      if (index < 0) {
        return UnsupportedError("line " + Num(lines.number()) + ": face " +
                                Num(d.polygons) +
                                " uses a negative (relative) vertex index " +
                                Num(index) + ", which sdcb does not support");
      }
      if (index == 0 || index > d.vertices) {
        return CorruptFileError(
            "line " + Num(lines.number()) + ": face " + Num(d.polygons) +
            " refers to vertex " + Num(index) + ", but the file has " +
            Num(d.vertices) + " vertices (OBJ indices run from 1)");
      }
    }
    d.triangles += corners - 2;
    if (++d.polygons > kMaxElements) {
      return CorruptFileError("the file has more than " + Num(kMaxElements) +
                              " faces");
    }
  }
  return d;
}

// ---------------------------------------------------------------------------
// PLY: the header is parsed here, then the whole body is walked (ascii as
// tokens, binary as bytes) to check counts, corner counts, indices and
// coordinates before OpenMesh sees the file.
struct PlyProperty {
  std::string name;
  int size = 0;        // bytes of the scalar (or of the list's items)
  int count_size = 0;  // > 0 for lists: bytes of the count
  std::string type, count_type;
};
struct PlyElement {
  std::string name;
  int64_t count = 0;
  std::vector<PlyProperty> properties;
};

int PlyTypeSize(std::string_view type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8")
    return 1;
  if (type == "short" || type == "ushort" || type == "int16" ||
      type == "uint16")
    return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" ||
      type == "float" || type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

bool PlyTypeIsFloat(std::string_view type) {
  return type == "float" || type == "float32" || type == "double" ||
         type == "float64";
}

// Reads a binary PLY scalar as double.
double PlyBinaryValue(const unsigned char* p, const std::string& type,
                      bool big_endian) {
  unsigned char b[8];
  const int n = PlyTypeSize(type);
  for (int i = 0; i < n; ++i) b[i] = big_endian ? p[n - 1 - i] : p[i];
  if (type == "char" || type == "int8") {
    int8_t v;
    std::memcpy(&v, b, 1);
    return v;
  }
  if (type == "uchar" || type == "uint8") {
    uint8_t v;
    std::memcpy(&v, b, 1);
    return v;
  }
  if (type == "short" || type == "int16") {
    int16_t v;
    std::memcpy(&v, b, 2);
    return v;
  }
  if (type == "ushort" || type == "uint16") {
    uint16_t v;
    std::memcpy(&v, b, 2);
    return v;
  }
  if (type == "int" || type == "int32") {
    int32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  if (type == "uint" || type == "uint32") {
    uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  if (type == "float" || type == "float32") {
    float v;
    std::memcpy(&v, b, 4);
    return v;
  }
  double v;
  std::memcpy(&v, b, 8);
  return v;
}

StatusOr<Declared> ScanPly(const std::string& text) {
  LineCursor lines(text);
  std::string_view line;
  if (!lines.Next(&line) || Tokens(line).empty() || Tokens(line)[0] != "ply") {
    return CorruptFileError("the file does not start with 'ply'");
  }
  if (text.find("\nend_header") == std::string::npos) {
    return CorruptFileError("the PLY header has no 'end_header'");
  }
  std::string format;
  std::vector<PlyElement> elements;
  bool ended = false;
  size_t body_offset = 0;
  size_t consumed = line.size() + 1;
  while (lines.Next(&line)) {
    consumed += line.size() + 1;
    const auto t = Tokens(line);
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format" && t.size() >= 2) {
      format = std::string(t[1]);
    } else if (t[0] == "element" && t.size() >= 3) {
      PlyElement e;
      e.name = std::string(t[1]);
      if (!ParseInt(t[2], &e.count)) {
        return CorruptFileError("element '" + e.name + "' has a bad count '" +
                                std::string(t[2]) + "'");
      }
      SDCB_RETURN_IF_ERROR(CheckCount(e.count, (e.name + " elements").c_str()));
      elements.push_back(e);
    } else if (t[0] == "property" && !elements.empty()) {
      PlyProperty p;
      if (t.size() >= 5 && t[1] == "list") {
        p.count_type = std::string(t[2]);
        p.type = std::string(t[3]);
        p.name = std::string(t[4]);
        p.count_size = PlyTypeSize(p.count_type);
        p.size = PlyTypeSize(p.type);
        if (p.count_size == 0 || p.size == 0 || PlyTypeIsFloat(p.count_type)) {
          return CorruptFileError("property list '" + p.name +
                                  "' has an unknown type");
        }
      } else if (t.size() >= 3) {
        p.type = std::string(t[1]);
        p.name = std::string(t[2]);
        p.size = PlyTypeSize(p.type);
        if (p.size == 0) {
          return CorruptFileError("property '" + p.name +
                                  "' has unknown type '" + p.type + "'");
        }
      } else {
        return CorruptFileError("line " + Num(lines.number()) +
                                " of the header is a malformed property");
      }
      elements.back().properties.push_back(p);
    } else if (t[0] == "end_header") {
      ended = true;
      body_offset = std::min(consumed, text.size());
      break;
    }
  }
  if (!ended) return CorruptFileError("the PLY header has no 'end_header'");
  const bool ascii = format == "ascii";
  const bool big_endian = format == "binary_big_endian";
  if (!ascii && !big_endian && format != "binary_little_endian") {
    return CorruptFileError("unknown PLY format '" + format + "'");
  }

  Declared d;
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  for (const auto& e : elements) {
    if (e.name == "vertex") vertex = &e;
    if (e.name == "face") face = &e;
  }
  if (vertex == nullptr)
    return CorruptFileError("the PLY file has no vertex element");
  d.vertices = vertex->count;
  d.polygons = face ? face->count : 0;
  d.coordinates.assign(3 * d.vertices, 0.0);
  int coordinate_slot[3] = {-1, -1, -1};
  for (size_t i = 0; i < vertex->properties.size(); ++i) {
    const auto& name = vertex->properties[i].name;
    if (name.size() == 1 && name[0] >= 'x' && name[0] <= 'z') {
      coordinate_slot[name[0] - 'x'] = static_cast<int>(i);
    }
  }
  if (coordinate_slot[0] < 0 || coordinate_slot[1] < 0 ||
      coordinate_slot[2] < 0) {
    return CorruptFileError("the vertex element lacks x, y or z");
  }

  // Minimum body size, to refuse absurd counts before walking.
  int64_t min_bytes = 0;
  for (const auto& e : elements) {
    int64_t per_item = 0;
    for (const auto& p : e.properties) {
      per_item += ascii ? 2 : (p.count_size > 0 ? p.count_size : p.size);
    }
    min_bytes += per_item * e.count;
  }
  const int64_t body_bytes = static_cast<int64_t>(text.size() - body_offset);
  if (min_bytes > body_bytes) {
    return CorruptFileError("the header declares " + Num(d.vertices) +
                            " vertices and " + Num(d.polygons) +
                            " faces, which need at least " + Num(min_bytes) +
                            " bytes, but only " + Num(body_bytes) +
                            " follow the header (truncated file?)");
  }

  // Walk the body.
  size_t pos = body_offset;
  const size_t end = text.size();
  auto next_ascii = [&](std::string_view* token) {
    while (pos < end && std::isspace(static_cast<unsigned char>(text[pos])))
      ++pos;
    size_t j = pos;
    while (j < end && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
    if (j == pos) return false;
    *token = std::string_view(text).substr(pos, j - pos);
    pos = j;
    return true;
  };
  auto next_value = [&](const std::string& type, double* value) -> bool {
    if (ascii) {
      std::string_view token;
      return next_ascii(&token) && ParseFinite(token, value);
    }
    const int n = PlyTypeSize(type);
    if (pos + n > end) return false;
    *value = PlyBinaryValue(
        reinterpret_cast<const unsigned char*>(text.data()) + pos, type,
        big_endian);
    pos += n;
    return std::isfinite(*value);
  };
  const std::string truncated = "the file is truncated or malformed in the ";
  for (const auto& e : elements) {
    const bool is_vertex = &e == vertex, is_face = &e == face;
    for (int64_t item = 0; item < e.count; ++item) {
      for (size_t pi = 0; pi < e.properties.size(); ++pi) {
        const auto& p = e.properties[pi];
        double value;
        if (p.count_size == 0) {
          if (!next_value(p.type, &value)) {
            if (is_vertex && pos <= end &&
                (pi == static_cast<size_t>(coordinate_slot[0]) ||
                 pi == static_cast<size_t>(coordinate_slot[1]) ||
                 pi == static_cast<size_t>(coordinate_slot[2]))) {
              return CorruptFileError(
                  "vertex " + Num(item) +
                  " has a missing or non-finite coordinate");
            }
            return CorruptFileError(truncated + e.name + " element " +
                                    Num(item));
          }
          if (is_vertex) {
            for (int axis = 0; axis < 3; ++axis) {
              if (pi == static_cast<size_t>(coordinate_slot[axis])) {
                d.coordinates[3 * item + axis] = value;
              }
            }
          }
          continue;
        }
        double count;
        if (!next_value(p.count_type, &count) || count < 0 ||
            count != std::floor(count)) {
          return CorruptFileError(truncated + e.name + " element " + Num(item));
        }
        const bool corner_list =
            is_face && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (corner_list) {
          SDCB_RETURN_IF_ERROR(
              CheckPolygon(item, static_cast<int64_t>(count), d.vertices));
          d.triangles += static_cast<int64_t>(count) - 2;
        } else if (count > kMaxPolygonCorners) {
          return CorruptFileError("a list in " + e.name + " element " +
                                  Num(item) + " declares " +
                                  Num(static_cast<int64_t>(count)) + " items");
        }
        for (int64_t k = 0; k < static_cast<int64_t>(count); ++k) {
          if (!next_value(p.type, &value)) {
            return CorruptFileError(truncated + e.name + " element " +
                                    Num(item));
          }
          if (corner_list) {
            SDCB_RETURN_IF_ERROR(
                CheckIndex(item, static_cast<int64_t>(value), d.vertices));
          }
        }
      }
    }
  }
  return d;
}

// ---------------------------------------------------------------------------
// STL: binary when the size is exactly 84 + 50 n (the rule OpenMesh applies
// too), ascii when it starts with "solid" and is not binary-sized.
StatusOr<Declared> ScanStl(const std::string& text) {
  Declared d;
  const size_t size = text.size();
  uint32_t declared = 0;
  if (size >= 84) std::memcpy(&declared, text.data() + 80, 4);
  const bool binary_sized = size >= 84 && size == 84 + 50 * uint64_t{declared};
  size_t first = text.find_first_not_of(" \t\r\n");
  const bool starts_solid =
      first != std::string::npos && text.compare(first, 5, "solid") == 0;
  if (binary_sized) {
    d.polygons = d.triangles = declared;
    SDCB_RETURN_IF_ERROR(CheckCount(d.polygons, "triangles"));
    d.vertices = 3 * d.polygons;  // before merging shared corners
    for (uint32_t t = 0; t < declared; ++t) {
      for (int k = 0; k < 9; ++k) {
        float c;
        std::memcpy(&c, text.data() + 84 + 50 * size_t{t} + 12 + 4 * k, 4);
        if (!std::isfinite(c)) {
          return CorruptFileError("triangle " + Num(t) +
                                  " has a non-finite coordinate");
        }
      }
    }
    return d;
  }
  if (!starts_solid) {
    if (size < 84) {
      return CorruptFileError(
          "the file is " + Num(size) +
          " bytes, too short for a binary STL, and is not ASCII STL");
    }
    return CorruptFileError(
        "truncated or corrupt binary STL: the header declares " +
        Num(declared) + " triangles (" + Num(84 + 50 * int64_t{declared}) +
        " bytes), but the file has " + Num(size) + " bytes");
  }
  // ASCII: facet normal n n n / outer loop / vertex x y z (x3) / endloop /
  // endfacet, repeated, then endsolid.
  LineCursor lines(text);
  std::string_view line;
  int corners = 0;
  bool in_facet = false;
  bool finished = false;
  while (lines.Next(&line)) {
    const auto t = Tokens(line);
    if (t.empty()) continue;
    if (t[0] == "facet") {
      if (in_facet) break;
      in_facet = true;
      corners = 0;
    } else if (t[0] == "vertex") {
      double x;
      if (!in_facet || t.size() < 4 || !ParseFinite(t[1], &x) ||
          !ParseFinite(t[2], &x) || !ParseFinite(t[3], &x)) {
        return CorruptFileError("line " + Num(lines.number()) +
                                ": malformed or non-finite STL vertex");
      }
      ++corners;
    } else if (t[0] == "endfacet") {
      if (!in_facet || corners != 3) {
        return CorruptFileError(
            "line " + Num(lines.number()) +
            ": an STL facet must have exactly three vertices");
      }
      in_facet = false;
      ++d.polygons;
    } else if (t[0] == "endsolid") {
      finished = !in_facet;
      break;
    }
  }
  if (!finished) {
    return CorruptFileError(
        "the ASCII STL is truncated (no matching 'endsolid')");
  }
  d.triangles = d.polygons;
  d.vertices = 3 * d.polygons;
  return d;
}

std::string WithoutCommentLines(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  LineCursor lines(text);
  std::string_view line;
  while (lines.Next(&line)) {
    if (IsBlankOrComment(line)) continue;
    out.append(line.data(), line.size());
    out.push_back('\n');
  }
  return out;
}

StatusOr<std::string> WriteTemporaryCopy(const std::string& text,
                                         const std::string& ext) {
  std::error_code ec;
  const fs::path dir = fs::temp_directory_path(ec);
  if (ec) return IoError("no temporary directory is available");
  std::string name = (dir / "sdcb-mesh-XXXXXX").string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0) return IoError("cannot create a temporary file");
  ::close(fd);
  const std::string path = name + ext;
  if (std::rename(name.c_str(), path.c_str()) != 0) {
    std::remove(name.c_str());
    return IoError("cannot create a temporary file");
  }
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) {
    std::remove(path.c_str());
    return IoError("cannot write a temporary file");
  }
  return path;
}

std::string LowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

StatusOr<TriangleMesh> ReadMeshUnprefixed(const std::string& path,
                                          MeshReadInfo* info) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) return IoError("no such file");
  if (fs::is_directory(st)) return IoError("is a directory, not a mesh file");
  if (!fs::is_regular_file(st)) return IoError("is not a regular file");
  const std::string ext = LowerExtension(path);
  if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl") {
    return UnsupportedError("unknown mesh format '" + ext +
                            "' (sdcb reads .obj, .off, .ply and .stl)");
  }
  SDCB_ASSIGN_OR_RETURN(const std::string text, ReadWholeFile(path));
  if (text.empty()) return CorruptFileError("the file is empty");

  Declared declared;
  if (ext == ".off") {
    SDCB_ASSIGN_OR_RETURN(declared, ScanOff(text));
  } else if (ext == ".obj") {
    SDCB_ASSIGN_OR_RETURN(declared, ScanObj(text));
  } else if (ext == ".ply") {
    SDCB_ASSIGN_OR_RETURN(declared, ScanPly(text));
  } else {
    SDCB_ASSIGN_OR_RETURN(declared, ScanStl(text));
  }
  if (declared.polygons == 0) return InvalidInputError("the mesh has no faces");

  // OpenMesh's logging goes to std::cerr; the library must stay silent.
  omerr().disable();
  omlog().disable();
  omout().disable();
  // Some of its readers also print straight to std::cerr: silenced while it
  // runs (not thread-safe with other users of std::cerr).
  struct CerrSilencer {
    std::ostringstream sink;
    std::streambuf* saved = std::cerr.rdbuf(sink.rdbuf());
    ~CerrSilencer() { std::cerr.rdbuf(saved); }
  } silence_cerr;
  RawImporter importer;
  OpenMesh::IO::Options options;
  bool read_ok = false;
  try {
    if (!declared.has_comments) {
      read_ok = OpenMesh::IO::IOManager().read(path, importer, options);
    } else {
      // (OpenMesh's stream reader misdetects ascii OFF as binary, so the
      // copy goes through a private temporary file.)
      SDCB_ASSIGN_OR_RETURN(const std::string copy,
                            WriteTemporaryCopy(WithoutCommentLines(text), ext));
      read_ok = OpenMesh::IO::IOManager().read(copy, importer, options);
      std::remove(copy.c_str());
    }
  } catch (const std::exception& e) {
    return CorruptFileError(std::string("the mesh reader failed: ") + e.what());
  } catch (...) {
    return CorruptFileError("the mesh reader failed");
  }
  if (!read_ok)
    return CorruptFileError("the file could not be parsed as a mesh");

  const int64_t polygons = static_cast<int64_t>(importer.polygons.size());
  if (polygons != declared.polygons) {
    return CorruptFileError("the file declares " + Num(declared.polygons) +
                            " faces, but only " + Num(polygons) +
                            " could be read");
  }
  if (ext != ".stl" &&
      static_cast<int64_t>(importer.points.size()) != declared.vertices) {
    return CorruptFileError("the file declares " + Num(declared.vertices) +
                            " vertices, but " + Num(importer.points.size()) +
                            " were read");
  }

  TriangleMesh mesh;
  const int nv = static_cast<int>(importer.points.size());
  mesh.vertices.resize(nv, 3);
  // The scan's double-precision values replace OpenMesh's floats; they
  // must agree up to float rounding (a disagreement is a bug, not bad input).
  const bool exact = declared.coordinates.size() == 3 * static_cast<size_t>(nv);
  for (int v = 0; v < nv; ++v) {
    for (int k = 0; k < 3; ++k) {
      double c = importer.points[v][k];
      if (exact) {
        const double d = declared.coordinates[3 * v + k];
        if (std::abs(static_cast<double>(static_cast<float>(d)) - c) >
            1e-6 * std::abs(d) + 1e-30) {
          return InternalError("vertex " + Num(v) +
                               " was parsed differently by sdcb and OpenMesh");
        }
        c = d;
      }
      if (!std::isfinite(c)) {
        return InvalidInputError("vertex " + Num(v) +
                                 " has a non-finite coordinate");
      }
      mesh.vertices(v, k) = c;
    }
  }
  int64_t triangles = 0;
  MeshReadInfo local;
  for (const auto& polygon : importer.polygons) {
    if (polygon.size() < 3) {
      return CorruptFileError("a face with fewer than three corners was read");
    }
    triangles += static_cast<int64_t>(polygon.size()) - 2;
    if (polygon.size() > 3) ++local.triangulated_polygons;
  }
  mesh.faces.resize(triangles, 3);
  int64_t row = 0;
  for (const auto& polygon : importer.polygons) {
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
      const int corner[3] = {polygon[0], polygon[k], polygon[k + 1]};
      for (int c = 0; c < 3; ++c) {
        if (corner[c] < 0 || corner[c] >= nv) {
          return CorruptFileError("a face refers to vertex " + Num(corner[c]) +
                                  ", but the file has " + Num(nv) +
                                  " vertices");
        }
        mesh.faces(row, c) = corner[c];
      }
      ++row;
    }
  }
  local.polygons = static_cast<int>(polygons);
  if (info != nullptr) *info = local;
  return mesh;
}

}  // namespace

StatusOr<TriangleMesh> ReadMesh(const std::string& path, MeshReadInfo* info) {
  StatusOr<TriangleMesh> mesh = ReadMeshUnprefixed(path, info);
  if (!mesh.ok()) return mesh.status().WithPrefix(path);
  return mesh;
}

}  // namespace sdcb
