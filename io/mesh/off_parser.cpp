// OFF (ascii): a header keyword ([ST][C][N]OFF), the counts "V F [E]" (on
// the keyword's line or the next), V vertex lines of at least three numbers
// (extra values: colors, normals, texture coordinates, ignored), F face
// lines "n i_1 .. i_n [color]". '#' starts a comment anywhere; blank lines
// are skipped.
#include <vector>

#include "sdcb/io/mesh/mesh_parsing.h"

namespace sdcb::mesh_parsing {
namespace {

// The next line that is not blank after removing its comment.
bool NextContentLine(LineCursor* lines, std::string_view* line) {
  while (lines->Next(line)) {
    *line = WithoutComment(*line);
    if (!Tokenizer(*line).AtEnd()) return true;
  }
  return false;
}

Status CheckCount(int64_t count, const char* what) {
  if (count < 0) {
    return CorruptFileError(
        std::string("the header declares a negative number of ") + what + " (" +
        Num(count) + ")");
  }
  return Status::Ok();
}

}  // namespace

Status ParseOff(std::string_view text, const MeshReadLimits& limits,
                MeshBuilder* builder) {
  LineCursor lines(text);
  std::string_view line;
  if (!NextContentLine(&lines, &line)) {
    return CorruptFileError("the file has no OFF header");
  }
  Tokenizer header(line);
  std::string_view keyword;
  header.Next(&keyword);
  // [ST][C][N][4][n]OFF; the 4 and n variants have other dimensions.
  const bool is_off =
      keyword.size() >= 3 && keyword.substr(keyword.size() - 3) == "OFF" &&
      keyword.find_first_not_of("STCN4nOF") == std::string_view::npos;
  if (!is_off) {
    return CorruptFileError("the first line is " + Quoted(keyword) +
                            ", not an OFF header");
  }
  if (keyword.find_first_of("4n") != std::string_view::npos) {
    return UnsupportedError(Quoted(keyword) +
                            " (higher-dimensional OFF) is not supported");
  }
  // The counts follow the keyword on its line or on the next one.
  std::string_view counts_line =
      line.substr(keyword.data() + keyword.size() - line.data());
  Tokenizer counts(counts_line);
  std::string_view token;
  if (counts.AtEnd()) {
    if (!NextContentLine(&lines, &counts_line)) counts_line = {};
    counts = Tokenizer(counts_line);
  }
  int64_t num_vertices = 0, num_faces = 0;
  if (!counts.Next(&token)) {
    return CorruptFileError("the OFF header has no vertex and face counts");
  }
  if (token == "BINARY") {
    return UnsupportedError("binary OFF is not supported");
  }
  if (!ParseInt64(token, &num_vertices) || !counts.Next(&token) ||
      !ParseInt64(token, &num_faces)) {
    return CorruptFileError(
        "line " + Num(lines.number()) +
        ": the OFF header has no valid vertex and face counts");
  }
  SDCB_RETURN_IF_ERROR(CheckCount(num_vertices, "vertices"));
  SDCB_RETURN_IF_ERROR(CheckCount(num_faces, "faces"));
  // Each vertex line takes at least 6 bytes ("0 0 0\n"), each face 8.
  if (num_vertices > static_cast<int64_t>(text.size()) / 6 ||
      num_faces > static_cast<int64_t>(text.size()) / 8 ||
      6 * num_vertices + 8 * num_faces > static_cast<int64_t>(text.size())) {
    return CorruptFileError("the header declares " + Num(num_vertices) +
                            " vertices and " + Num(num_faces) +
                            " faces, which cannot fit in " + Num(text.size()) +
                            " bytes (truncated file?)");
  }
  SDCB_RETURN_IF_ERROR(builder->Reserve(num_vertices, num_faces));

  for (int64_t v = 0; v < num_vertices; ++v) {
    if (!NextContentLine(&lines, &line)) {
      return CorruptFileError("the file is truncated: it declares " +
                              Num(num_vertices) + " vertices but holds " +
                              Num(v));
    }
    Tokenizer values(line);
    double xyz[3];
    for (int k = 0; k < 3; ++k) {
      if (!values.Next(&token)) {
        return CorruptFileError("line " + Num(lines.number()) + ": vertex " +
                                Num(v) + " has fewer than three coordinates");
      }
      if (!ParseFiniteDouble(token, &xyz[k])) {
        return CorruptFileError("line " + Num(lines.number()) + ": vertex " +
                                Num(v) + " has coordinate " + Quoted(token) +
                                ", which is not a finite number");
      }
    }
    SDCB_RETURN_IF_ERROR(builder->AddVertex(xyz[0], xyz[1], xyz[2]));
  }
  std::vector<int> corners;
  for (int64_t f = 0; f < num_faces; ++f) {
    if (!NextContentLine(&lines, &line)) {
      return CorruptFileError("the file is truncated: it declares " +
                              Num(num_faces) + " faces but holds " + Num(f));
    }
    auto where = [&] { return "line " + Num(lines.number()) + ": "; };
    Tokenizer values(line);
    int64_t n = 0;
    if (!values.Next(&token) || !ParseInt64(token, &n)) {
      return CorruptFileError(where() + "face " + Num(f) +
                              " does not start with a corner count");
    }
    SDCB_RETURN_IF_ERROR(CheckCorners(f, n, num_vertices, limits)
                             .WithPrefix("line " + Num(lines.number())));
    corners.clear();
    for (int64_t k = 0; k < n; ++k) {
      int64_t index = 0;
      if (!values.Next(&token)) {
        return CorruptFileError(where() + "face " + Num(f) + " declares " +
                                Num(n) + " corners but lists " + Num(k));
      }
      if (!ParseInt64(token, &index)) {
        return CorruptFileError(where() + "face " + Num(f) + " has a corner " +
                                Quoted(token) + " that is not an index");
      }
      if (index < 0 || index >= num_vertices) {
        return CorruptFileError(
            where() + "face " + Num(f) + " refers to vertex " + Num(index) +
            ", but the file has " + Num(num_vertices) +
            " vertices (valid: 0.." + Num(num_vertices - 1) + ")");
      }
      corners.push_back(static_cast<int>(index));
    }
    // Anything after the corners is a color; it is not needed.
    SDCB_RETURN_IF_ERROR(builder->AddPolygon(corners.data(), n));
  }
  return Status::Ok();
}

}  // namespace sdcb::mesh_parsing
