// PLY (ascii, binary_little_endian, binary_big_endian 1.0). The header is
// parsed strictly: "ply", one "format" line, "element NAME COUNT" lines each
// followed by its "property TYPE NAME" / "property list CTYPE TYPE NAME"
// lines, "comment" / "obj_info" lines anywhere, "end_header". A line that
// starts with no keyword is free text (Blender 2.47 wrote "Created by
// Blender3D 247 - www.blender.org, source file: ..." without "comment"): it
// is ignored with a warning, and an error that follows names it, since it
// may be a misspelt keyword. Then the body
// is walked element by element: x, y, z of "vertex" (any numeric type) are
// kept, "face" needs a "vertex_indices" (or "vertex_index") list of an
// integer type; every other element and property is stepped over.
#include <cmath>
#include <cstring>
#include <vector>

#include "sdcb/io/mesh/mesh_parsing.h"

namespace sdcb::mesh_parsing {
namespace {

enum class PlyType {
  kInvalid,
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kFloat32,
  kFloat64
};

PlyType TypeFromName(std::string_view name) {
  if (name == "char" || name == "int8") return PlyType::kInt8;
  if (name == "uchar" || name == "uint8") return PlyType::kUint8;
  if (name == "short" || name == "int16") return PlyType::kInt16;
  if (name == "ushort" || name == "uint16") return PlyType::kUint16;
  if (name == "int" || name == "int32") return PlyType::kInt32;
  if (name == "uint" || name == "uint32") return PlyType::kUint32;
  if (name == "float" || name == "float32") return PlyType::kFloat32;
  if (name == "double" || name == "float64") return PlyType::kFloat64;
  return PlyType::kInvalid;
}

int SizeOf(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
    case PlyType::kInvalid:
      break;
  }
  return 0;
}

bool IsInteger(PlyType type) {
  return type != PlyType::kFloat32 && type != PlyType::kFloat64 &&
         type != PlyType::kInvalid;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kInvalid;        // of the value / the list items
  PlyType count_type = PlyType::kInvalid;  // lists only
  bool is_list() const { return count_type != PlyType::kInvalid; }
};

struct PlyElement {
  std::string name;
  int64_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { kAscii, kLittleEndian, kBigEndian };

// Header lines that start with no keyword (free text), ignored.
struct PlyFreeText {
  int64_t lines = 0;
  int64_t first_line = 0;  // 1-based line number of the first
  std::string first_text;  // the first, quoted

  // "line 3 of the header ('Created by ...') is not a PLY keyword line" and,
  // for several, "(and 2 more lines)"; empty when there are none.
  std::string Describe() const {
    if (lines == 0) return "";
    std::string s = "line " + Num(first_line) + " of the header (" +
                    first_text + ") is not a PLY keyword line";
    if (lines > 1) {
      s += " (nor are " + Num(lines - 1) +
           (lines == 2 ? " other line)" : " other lines)");
    }
    return s;
  }
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;
  PlyFreeText free_text;
};

// The header's lines up to end_header; free-text lines are counted in
// `free_text`, not refused.
StatusOr<PlyHeader> ParseHeaderLines(std::string_view bytes,
                                     PlyFreeText* free_text) {
  LineCursor lines(bytes);
  std::string_view line, token;
  bool starts_with_ply = lines.Next(&line);
  if (starts_with_ply) {
    Tokenizer first(line);
    starts_with_ply = first.Next(&token) && token == "ply" && first.AtEnd();
  }
  if (!starts_with_ply) {
    return CorruptFileError("the file does not start with 'ply'");
  }
  PlyHeader header;
  bool has_format = false;
  while (lines.Next(&line)) {
    auto where = [&] {
      return "line " + Num(lines.number()) + " of the PLY header: ";
    };
    Tokenizer tokens(line);
    std::vector<std::string_view> t;
    // Comments may hold anything; other lines have at most 5 tokens.
    if (!tokens.Next(&token)) continue;
    if (token == "comment" || token == "obj_info") continue;
    t.push_back(token);
    while (t.size() <= 5 && tokens.Next(&token)) t.push_back(token);
    if (t[0] == "end_header") {
      if (t.size() != 1) return CorruptFileError(where() + "malformed");
      if (!has_format) {
        return CorruptFileError("the PLY header has no 'format' line");
      }
      header.body_offset = lines.offset();
      header.free_text = *free_text;
      return header;
    }
    if (t[0] == "format") {
      double version = 0.0;
      if (has_format || t.size() != 3 || !ParseFiniteDouble(t[2], &version) ||
          version != 1.0) {
        return CorruptFileError(where() +
                                "expected one 'format FORMAT 1.0' line");
      }
      if (t[1] == "ascii") {
        header.format = PlyFormat::kAscii;
      } else if (t[1] == "binary_little_endian") {
        header.format = PlyFormat::kLittleEndian;
      } else if (t[1] == "binary_big_endian") {
        header.format = PlyFormat::kBigEndian;
      } else {
        return CorruptFileError(where() + "unknown PLY format " + Quoted(t[1]));
      }
      has_format = true;
    } else if (t[0] == "element") {
      PlyElement e;
      if (t.size() != 3) {
        return CorruptFileError(where() + "expected 'element NAME COUNT'");
      }
      e.name = std::string(t[1]);
      if (!ParseInt64(t[2], &e.count)) {
        return CorruptFileError(where() + "element '" + e.name +
                                "' has a bad count " + Quoted(t[2]));
      }
      if (e.count < 0) {
        return CorruptFileError("the header declares a negative number of " +
                                e.name + " elements (" + Num(e.count) + ")");
      }
      for (const PlyElement& other : header.elements) {
        if (other.name == e.name) {
          return CorruptFileError(where() + "a second element " +
                                  Quoted(e.name));
        }
      }
      header.elements.push_back(std::move(e));
    } else if (t[0] == "property") {
      if (header.elements.empty()) {
        return CorruptFileError(where() + "a property before any element");
      }
      PlyProperty p;
      if (t.size() == 5 && t[1] == "list") {
        p.count_type = TypeFromName(t[2]);
        p.type = TypeFromName(t[3]);
        p.name = std::string(t[4]);
        if (!IsInteger(p.count_type) || p.type == PlyType::kInvalid) {
          return CorruptFileError(where() + "property list '" + p.name +
                                  "' has an unknown or non-integer count type");
        }
      } else if (t.size() == 3 && t[1] != "list") {
        p.type = TypeFromName(t[1]);
        p.name = std::string(t[2]);
        if (p.type == PlyType::kInvalid) {
          return CorruptFileError(where() + "property '" + p.name +
                                  "' has unknown type " + Quoted(t[1]));
        }
      } else {
        return CorruptFileError(where() + "a malformed property");
      }
      header.elements.back().properties.push_back(std::move(p));
    } else {
      if (free_text->lines++ == 0) {
        size_t begin = 0, end = line.size();
        while (begin < end && IsSpace(line[begin])) ++begin;
        while (end > begin && IsSpace(line[end - 1])) --end;
        free_text->first_line = lines.number();
        free_text->first_text = Quoted(line.substr(begin, end - begin));
      }
    }
  }
  return CorruptFileError("the PLY header has no 'end_header'");
}

// Appends to an error the free-text lines that preceded it: one may be a
// misspelt keyword ("elemnt vertex 3").
Status NamingFreeText(const Status& status, const PlyFreeText& free_text) {
  if (status.ok() || free_text.lines == 0) return status;
  return Status(status.code(), status.message() + " (" + free_text.Describe() +
                                   ", and was ignored)");
}

StatusOr<PlyHeader> ParseHeader(std::string_view bytes) {
  PlyFreeText free_text;
  StatusOr<PlyHeader> header = ParseHeaderLines(bytes, &free_text);
  if (!header.ok()) return NamingFreeText(header.status(), free_text);
  return header;
}

// Reads the body's values one at a time, as text tokens or binary scalars.
class PlyValueReader {
 public:
  PlyValueReader(std::string_view body, PlyFormat format)
      : body_(body), format_(format), tokens_(body) {}

  // The next value as a double; false at the end of the data or for an
  // ascii token that is not a finite number.
  bool Read(PlyType type, double* value) {
    if (format_ == PlyFormat::kAscii) {
      std::string_view token;
      return tokens_.Next(&token) && ParseFiniteDouble(token, value);
    }
    const size_t n = static_cast<size_t>(SizeOf(type));
    if (body_.size() - pos_ < n) return false;
    unsigned char b[8];
    for (size_t i = 0; i < n; ++i) {
      b[i] = static_cast<unsigned char>(
          body_[pos_ + (format_ == PlyFormat::kBigEndian ? n - 1 - i : i)]);
    }
    pos_ += n;
    *value = Decode(b, type);
    return true;
  }

  // An integer value (a list count or an index).
  bool ReadInteger(PlyType type, int64_t* value) {
    if (format_ == PlyFormat::kAscii) {
      std::string_view token;
      return tokens_.Next(&token) && ParseInt64(token, value);
    }
    double v;
    if (!Read(type, &v)) return false;
    *value = static_cast<int64_t>(v);  // exact: integer types only
    return true;
  }

  // Steps over `count` values; false if the data ends first.
  bool Skip(PlyType type, int64_t count) {
    if (format_ == PlyFormat::kAscii) {
      std::string_view token;
      for (int64_t i = 0; i < count; ++i) {
        if (!tokens_.Next(&token)) return false;
      }
      return true;
    }
    const int64_t size = SizeOf(type);
    if (count > static_cast<int64_t>(body_.size() - pos_) / size) return false;
    pos_ += static_cast<size_t>(count * size);
    return true;
  }

 private:
  template <typename T>
  static double As(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof(T));
    return static_cast<double>(v);
  }

  static double Decode(const unsigned char* b, PlyType type) {
    switch (type) {
      case PlyType::kInt8:
        return As<int8_t>(b);
      case PlyType::kUint8:
        return As<uint8_t>(b);
      case PlyType::kInt16:
        return As<int16_t>(b);
      case PlyType::kUint16:
        return As<uint16_t>(b);
      case PlyType::kInt32:
        return As<int32_t>(b);
      case PlyType::kUint32:
        return As<uint32_t>(b);
      case PlyType::kFloat32:
        return As<float>(b);
      case PlyType::kFloat64:
      case PlyType::kInvalid:
        break;
    }
    return As<double>(b);
  }

  std::string_view body_;
  PlyFormat format_;
  Tokenizer tokens_;
  size_t pos_ = 0;
};

// Least bytes one item of `e` takes in the body (faces: three corners).
int64_t MinItemBytes(const PlyElement& e, PlyFormat format) {
  int64_t bytes = 0;
  const bool ascii = format == PlyFormat::kAscii;
  for (const PlyProperty& p : e.properties) {
    if (!p.is_list()) {
      bytes += ascii ? 2 : SizeOf(p.type);
      continue;
    }
    bytes += ascii ? 2 : SizeOf(p.count_type);
    if (e.name == "face" &&
        (p.name == "vertex_indices" || p.name == "vertex_index")) {
      bytes += 3 * (ascii ? 2 : SizeOf(p.type));
    }
  }
  return bytes;
}

Status ParseBody(const PlyHeader& header, std::string_view bytes,
                 const MeshReadLimits& limits, MeshBuilder* builder) {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  int xyz_slot[3] = {-1, -1, -1};
  int corner_slot = -1;
  for (const PlyElement& e : header.elements) {
    if (e.count > 0 && e.properties.empty()) {
      return CorruptFileError("the PLY element '" + e.name +
                              "' has items but no properties");
    }
    if (e.name == "vertex") vertex = &e;
    if (e.name == "face") face = &e;
  }
  if (vertex == nullptr) {
    return CorruptFileError("the PLY file has no vertex element");
  }
  for (size_t i = 0; i < vertex->properties.size(); ++i) {
    const PlyProperty& p = vertex->properties[i];
    if (p.name.size() == 1 && p.name[0] >= 'x' && p.name[0] <= 'z' &&
        !p.is_list()) {
      xyz_slot[p.name[0] - 'x'] = static_cast<int>(i);
    }
  }
  if (xyz_slot[0] < 0 || xyz_slot[1] < 0 || xyz_slot[2] < 0) {
    return CorruptFileError("the vertex element lacks x, y or z");
  }
  if (face != nullptr) {
    for (size_t i = 0; i < face->properties.size(); ++i) {
      const PlyProperty& p = face->properties[i];
      if (p.is_list() &&
          (p.name == "vertex_indices" || p.name == "vertex_index")) {
        corner_slot = static_cast<int>(i);
      }
    }
    if (corner_slot >= 0 && !IsInteger(face->properties[corner_slot].type)) {
      return CorruptFileError(
          "the face element's vertex indices are not "
          "of an integer type");
    }
    if (corner_slot < 0 && face->count > 0) {
      return CorruptFileError(
          "the face element has no vertex_indices list property");
    }
  }
  const int64_t num_vertices = vertex->count;
  const int64_t num_faces = face != nullptr ? face->count : 0;

  // Refuse counts the body cannot hold before allocating anything.
  const int64_t body_bytes =
      static_cast<int64_t>(bytes.size() - header.body_offset);
  int64_t min_bytes = 0;
  for (const PlyElement& e : header.elements) {
    const int64_t per_item = MinItemBytes(e, header.format);
    if (per_item > 0 && e.count > (body_bytes - min_bytes) / per_item) {
      min_bytes = body_bytes + 1;
      break;
    }
    min_bytes += per_item * e.count;
  }
  if (min_bytes > body_bytes) {
    return CorruptFileError(
        "the header declares " + Num(num_vertices) + " vertices and " +
        Num(num_faces) + " faces, which do not fit in the " + Num(body_bytes) +
        " bytes after the header (truncated file?)");
  }
  SDCB_RETURN_IF_ERROR(builder->Reserve(num_vertices, num_faces));

  PlyValueReader values(bytes.substr(header.body_offset), header.format);
  const std::string truncated = "the file is truncated or malformed in ";
  std::vector<int> corners;
  for (const PlyElement& e : header.elements) {
    const bool is_vertex = &e == vertex, is_face = &e == face;
    for (int64_t item = 0; item < e.count; ++item) {
      double xyz[3] = {0, 0, 0};
      for (size_t pi = 0; pi < e.properties.size(); ++pi) {
        const PlyProperty& p = e.properties[pi];
        auto where = [&] { return e.name + " element " + Num(item); };
        if (!p.is_list()) {
          const int axis = !is_vertex                            ? -1
                           : static_cast<int>(pi) == xyz_slot[0] ? 0
                           : static_cast<int>(pi) == xyz_slot[1] ? 1
                           : static_cast<int>(pi) == xyz_slot[2] ? 2
                                                                 : -1;
          if (axis < 0) {
            if (!values.Skip(p.type, 1)) {
              return CorruptFileError(truncated + where());
            }
          } else if (!values.Read(p.type, &xyz[axis]) ||
                     !std::isfinite(xyz[axis])) {
            return CorruptFileError("vertex " + Num(item) +
                                    " has a missing or non-finite coordinate");
          }
          continue;
        }
        int64_t count = 0;
        if (!values.ReadInteger(p.count_type, &count) || count < 0) {
          // Assimp's issue623.ply declares vertex_indices in the vertex
          // element: the next vertex's x is read as a count.
          return CorruptFileError(truncated + where() + " (its list '" +
                                  p.name + "' has no count of items)");
        }
        if (!is_face || static_cast<int>(pi) != corner_slot) {
          if (!values.Skip(p.type, count)) {
            return CorruptFileError(truncated + where());
          }
          continue;
        }
        SDCB_RETURN_IF_ERROR(CheckCorners(item, count, num_vertices, limits));
        corners.clear();
        for (int64_t k = 0; k < count; ++k) {
          int64_t index = 0;
          if (!values.ReadInteger(p.type, &index)) {
            return CorruptFileError(truncated + where());
          }
          if (index < 0 || index >= num_vertices) {
            return CorruptFileError(
                "face " + Num(item) + " refers to vertex " + Num(index) +
                ", but the file has " + Num(num_vertices) +
                " vertices (valid: 0.." + Num(num_vertices - 1) + ")");
          }
          corners.push_back(static_cast<int>(index));
        }
        SDCB_RETURN_IF_ERROR(builder->AddPolygon(corners.data(), count));
      }
      if (is_vertex) {
        SDCB_RETURN_IF_ERROR(builder->AddVertex(xyz[0], xyz[1], xyz[2]));
      }
    }
  }
  return Status::Ok();
}

}  // namespace

Status ParsePly(std::string_view bytes, const MeshReadLimits& limits,
                MeshBuilder* builder) {
  SDCB_ASSIGN_OR_RETURN(const PlyHeader header, ParseHeader(bytes));
  if (header.free_text.lines > 0) {
    builder->Warn(header.free_text.Describe() + "; ignored");
  }
  return NamingFreeText(ParseBody(header, bytes, limits, builder),
                        header.free_text);
}

}  // namespace sdcb::mesh_parsing
