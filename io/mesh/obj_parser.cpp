// OBJ: "v x y z [w | r g b]" and "f v[/vt][/vn] ..." lines; every other
// statement (vn, vt, o, g, s, l, p, usemtl, mtllib, ...) is skipped, and in
// particular no file named in it is ever opened. '#' starts a comment
// anywhere. Face indices run from 1 and may refer to vertices defined later
// in the file; a negative index is relative, -1 being the last vertex
// defined before the face.
#include <vector>

#include "sdcb/io/mesh/mesh_parsing.h"

namespace sdcb::mesh_parsing {

Status ParseObj(std::string_view text, const MeshReadLimits& limits,
                MeshBuilder* builder) {
  LineCursor lines(text);
  std::string_view line, token;
  std::vector<int> corners;
  // The largest index any face used, where: checked once all vertices are
  // known.
  int64_t largest = 0, largest_line = 0, largest_face = 0;
  while (lines.Next(&line)) {
    Tokenizer tokens(WithoutComment(line));
    if (!tokens.Next(&token)) continue;
    auto where = [&] { return "line " + Num(lines.number()) + ": "; };
    if (token == "v") {
      double xyz[3];
      for (int k = 0; k < 3; ++k) {
        if (!tokens.Next(&token)) {
          return CorruptFileError(where() + "vertex " +
                                  Num(builder->num_vertices()) +
                                  " has fewer than three coordinates");
        }
        if (!ParseFiniteDouble(token, &xyz[k])) {
          return CorruptFileError(where() + "vertex " +
                                  Num(builder->num_vertices()) +
                                  " has coordinate " + Quoted(token) +
                                  ", which is not a finite number");
        }
      }
      SDCB_RETURN_IF_ERROR(builder->AddVertex(xyz[0], xyz[1], xyz[2]));
    } else if (token == "f") {
      const int64_t face = builder->num_polygons();
      corners.clear();
      bool too_many = false;
      while (!too_many && tokens.Next(&token)) {
        too_many =
            static_cast<int64_t>(corners.size()) >= limits.max_polygon_corners;
        if (too_many) break;
        int64_t index = 0;
        const std::string_view head = token.substr(0, token.find('/'));
        if (!ParseInt64(head, &index)) {
          return CorruptFileError(where() + "face " + Num(face) +
                                  " has a corner " + Quoted(token) +
                                  " that is not an index");
        }
        if (index < 0) {
          // Relative: -1 is the last vertex defined so far.
          const int64_t defined = builder->num_vertices();
          if (index < -defined) {
            return CorruptFileError(
                where() + "face " + Num(face) + " refers to vertex " +
                Num(index) + ", but only " + Num(defined) +
                " vertices are defined before it (-1 is the last one)");
          }
          index += defined + 1;
        }
        if (index == 0 || index > limits.max_vertices) {
          return CorruptFileError(where() + "face " + Num(face) +
                                  " refers to vertex " + Num(index) +
                                  " (OBJ indices run from 1)");
        }
        if (index > largest) {
          largest = index;
          largest_line = lines.number();
          largest_face = face;
        }
        corners.push_back(static_cast<int>(index - 1));
      }
      if (too_many) {
        return UnsupportedError(where() + "face " + Num(face) +
                                " has more than " +
                                Num(limits.max_polygon_corners) + " corners");
      }
      const int64_t n = static_cast<int64_t>(corners.size());
      SDCB_RETURN_IF_ERROR(CheckCorners(face, n, -1, limits)
                               .WithPrefix("line " + Num(lines.number())));
      SDCB_RETURN_IF_ERROR(builder->AddPolygon(corners.data(), n));
    }
  }
  if (largest > builder->num_vertices()) {
    return CorruptFileError(
        "line " + Num(largest_line) + ": face " + Num(largest_face) +
        " refers to vertex " + Num(largest) + ", but the file has " +
        Num(builder->num_vertices()) + " vertices (OBJ indices run from 1)");
  }
  return Status::Ok();
}

}  // namespace sdcb::mesh_parsing
