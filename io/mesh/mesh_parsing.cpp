#include "sdcb/io/mesh/mesh_parsing.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <utility>

namespace sdcb::mesh_parsing {

std::string Num(int64_t x) { return std::to_string(x); }

// ---------------------------------------------------------------------------
// MeshBuilder

MeshBuilder::MeshBuilder(const MeshReadLimits& limits, size_t input_bytes,
                         int64_t bytes_per_corner)
    : limits_(limits),
      input_bytes_(static_cast<int64_t>(input_bytes)),
      bytes_per_corner_(bytes_per_corner) {}

Status MeshBuilder::CheckCounts(int64_t vertices, int64_t triangles) const {
  if (vertices > limits_.max_vertices) {
    return UnsupportedError("the mesh has more than " +
                            Num(limits_.max_vertices) +
                            " vertices, the limit for mesh files");
  }
  if (triangles > limits_.max_triangles) {
    return UnsupportedError("the mesh has more than " +
                            Num(limits_.max_triangles) +
                            " triangles, the limit for mesh files");
  }
  return Status::Ok();
}

Status MeshBuilder::CheckMemory(int64_t vertices, int64_t triangles) const {
  // Counts are below 2^32 here, so this cannot overflow.
  const int64_t estimate = input_bytes_ + 2 * (24 * vertices + 12 * triangles) +
                           bytes_per_corner_ * 3 * triangles;
  if (estimate > limits_.max_memory_bytes) {
    return UnsupportedError("reading the mesh would take about " +
                            Num(estimate >> 20) +
                            " MB of memory, more than the limit of " +
                            Num(limits_.max_memory_bytes >> 20) + " MB");
  }
  return Status::Ok();
}

Status MeshBuilder::Reserve(int64_t vertices, int64_t polygons) {
  SDCB_RETURN_IF_ERROR(CheckCounts(vertices, polygons));
  SDCB_RETURN_IF_ERROR(CheckMemory(vertices, polygons));
  coordinates_.reserve(3 * static_cast<size_t>(vertices));
  triangles_.reserve(3 * static_cast<size_t>(polygons));
  return Status::Ok();
}

Status MeshBuilder::AddVertex(double x, double y, double z) {
  const int64_t vertices = num_vertices() + 1;
  const int64_t triangles = num_triangles();
  SDCB_RETURN_IF_ERROR(CheckCounts(vertices, triangles));
  if (coordinates_.size() == coordinates_.capacity()) {
    // The array is about to double.
    SDCB_RETURN_IF_ERROR(CheckMemory(2 * vertices, triangles));
  }
  coordinates_.push_back(x);
  coordinates_.push_back(y);
  coordinates_.push_back(z);
  return Status::Ok();
}

Status MeshBuilder::AddPolygon(const int* corners, int64_t n) {
  const int64_t triangles = num_triangles() + n - 2;
  SDCB_RETURN_IF_ERROR(CheckCounts(num_vertices(), triangles));
  if (static_cast<size_t>(3 * triangles) > triangles_.capacity()) {
    // The array is about to grow to at least twice its size.
    SDCB_RETURN_IF_ERROR(
        CheckMemory(num_vertices(), std::max(triangles, 2 * num_triangles())));
  }
  const int64_t first_triangle = num_triangles();
  for (int64_t k = 1; k + 1 < n; ++k) {
    triangles_.push_back(corners[0]);
    triangles_.push_back(corners[k]);
    triangles_.push_back(corners[k + 1]);
  }
  if (n > 3 && n <= kMaxClippedCorners) {
    // Now when its corners are known (the usual case), else in Finish.
    const bool known = std::all_of(corners, corners + n, [&](int c) {
      return c >= 0 && c < num_vertices();
    });
    if (known) {
      ClipIfNotConvex(first_triangle, corners, static_cast<int>(n));
    } else {
      polygons_to_clip_.push_back(
          {first_triangle, static_cast<int64_t>(clipped_corners_.size()), n});
      clipped_corners_.insert(clipped_corners_.end(), corners, corners + n);
    }
  }
  ++polygons_;
  if (n > 3) ++triangulated_polygons_;
  return Status::Ok();
}

namespace {

// Twice the signed area of the 2-D triangle (a, b, c).
double Orient2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                const Eigen::Vector2d& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

}  // namespace

void MeshBuilder::ClipIfNotConvex(int64_t first_triangle, const int* corners,
                                  int n) {
  const int64_t nv = num_vertices();
  for (int i = 0; i < n; ++i) {
    if (corners[i] < 0 || corners[i] >= nv) return;  // the caller reports it
  }
  auto position = [&](int i) {
    const double* x = coordinates_.data() + 3 * static_cast<size_t>(corners[i]);
    return Eigen::Vector3d(x[0], x[1], x[2]);
  };
  // The polygon's plane: Newell's normal (the vector area), which a
  // non-planar or non-convex polygon still has.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i)
    normal += position(i).cross(position((i + 1) % n));
  if (!(normal.norm() > 0) || !normal.allFinite()) return;
  normal.normalize();
  const Eigen::Vector3d e1 = normal.unitOrthogonal();
  const Eigen::Vector3d e2 = normal.cross(e1);
  std::vector<Eigen::Vector2d> q(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d x = position(i);
    q[i] = Eigen::Vector2d(x.dot(e1), x.dot(e2));
  }
  // Counter-clockwise in (e1, e2) by construction; convex means every
  // corner turns left, and then the fan is right.
  bool convex = true;
  for (int i = 0; i < n && convex; ++i) {
    convex = Orient2d(q[(i + n - 1) % n], q[i], q[(i + 1) % n]) >= 0;
  }
  if (convex) return;
  // Ear clipping: cut off a corner that turns left and whose triangle holds
  // no other remaining corner; n - 2 ears, as many triangles as the fan.
  std::vector<int> left(n);
  for (int i = 0; i < n; ++i) left[i] = i;
  std::vector<int> ears;
  ears.reserve(3 * static_cast<size_t>(n - 2));
  while (left.size() > 3) {
    const int m = static_cast<int>(left.size());
    bool clipped = false;
    for (int j = 0; j < m && !clipped; ++j) {
      const int a = left[(j + m - 1) % m], b = left[j], c = left[(j + 1) % m];
      if (Orient2d(q[a], q[b], q[c]) <= 0) continue;
      bool empty = true;
      for (int k = 0; k < m && empty; ++k) {
        const int x = left[k];
        if (x == a || x == b || x == c) continue;
        empty = !(Orient2d(q[a], q[b], q[x]) >= 0 &&
                  Orient2d(q[b], q[c], q[x]) >= 0 &&
                  Orient2d(q[c], q[a], q[x]) >= 0);
      }
      if (!empty) continue;
      ears.insert(ears.end(), {a, b, c});
      left.erase(left.begin() + j);
      clipped = true;
    }
    if (!clipped) return;  // self-intersecting or degenerate: keep the fan
  }
  ears.insert(ears.end(), left.begin(), left.end());
  int* out = triangles_.data() + 3 * first_triangle;
  for (size_t k = 0; k < ears.size(); ++k) out[k] = corners[ears[k]];
}

TriangleMesh MeshBuilder::Finish(MeshReadInfo* info) {
  for (const PolygonToClip& p : polygons_to_clip_) {
    ClipIfNotConvex(p.first_triangle, clipped_corners_.data() + p.first_corner,
                    static_cast<int>(p.n));
  }
  std::vector<PolygonToClip>().swap(polygons_to_clip_);
  std::vector<int>().swap(clipped_corners_);
  TriangleMesh mesh;
  const Eigen::Index nv = static_cast<Eigen::Index>(coordinates_.size() / 3);
  const Eigen::Index nt = static_cast<Eigen::Index>(triangles_.size() / 3);
  mesh.vertices = Eigen::Map<
      const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      coordinates_.data(), nv, 3);
  std::vector<double>().swap(coordinates_);
  mesh.faces =
      Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
          triangles_.data(), nt, 3);
  std::vector<int>().swap(triangles_);
  if (info != nullptr) {
    info->polygons = static_cast<int>(polygons_);
    info->triangulated_polygons = static_cast<int>(triangulated_polygons_);
    info->warnings = std::move(warnings_);
  }
  return mesh;
}

Status CheckCorners(int64_t polygon, int64_t n, int64_t num_vertices,
                    const MeshReadLimits& limits) {
  if (n < 3 || n > limits.max_polygon_corners ||
      (num_vertices >= 0 && n > num_vertices)) {
    return CorruptFileError("face " + Num(polygon) + " declares " + Num(n) +
                            " corners");
  }
  return Status::Ok();
}

// ---------------------------------------------------------------------------
// Text

bool LineCursor::Next(std::string_view* line) {
  if (pos_ >= text_.size()) return false;
  size_t end = text_.find('\n', pos_);
  if (end == std::string_view::npos) end = text_.size();
  *line = text_.substr(pos_, end - pos_);
  pos_ = end + 1;
  ++number_;
  return true;
}

bool Tokenizer::Next(std::string_view* token) {
  while (pos_ < text_.size() && IsSpace(text_[pos_])) ++pos_;
  size_t end = pos_;
  while (end < text_.size() && !IsSpace(text_[end])) ++end;
  if (end == pos_) return false;
  *token = text_.substr(pos_, end - pos_);
  pos_ = end;
  return true;
}

bool Tokenizer::AtEnd() {
  while (pos_ < text_.size() && IsSpace(text_[pos_])) ++pos_;
  return pos_ == text_.size();
}

std::string_view WithoutComment(std::string_view line) {
  return line.substr(0, line.find('#'));
}

namespace {

bool IsDigit(char c, bool hex) {
  return (c >= '0' && c <= '9') ||
         (hex && ((c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F')));
}

// For a syntactically valid number whose value is out of the double range:
// true if its magnitude is >= 1 (an overflow), false if < 1 (an underflow).
// Position of the leading digit plus the exponent decides.
bool MagnitudeAtLeastOne(const char* p, const char* end, bool hex) {
  const char exponent_mark = hex ? 'p' : 'e';
  int64_t leading = 0;  // digit position of the first nonzero digit
  bool seen_point = false, found = false;
  int64_t integer_digits = 0, zeros_after_point = 0;
  for (; p < end && (*p | 0x20) != exponent_mark; ++p) {
    if (*p == '.') {
      seen_point = true;
    } else if (!found && *p == '0') {
      if (seen_point) ++zeros_after_point;
    } else {
      found = true;
      if (!seen_point) ++integer_digits;
    }
  }
  leading = integer_digits > 0 ? integer_digits - 1 : -(zeros_after_point + 1);
  if (hex) leading *= 4;
  int64_t exponent = 0;
  if (p < end) {
    ++p;
    bool negative = false;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    for (; p < end && exponent < 1'000'000'000; ++p)
      exponent = 10 * exponent + (*p - '0');
    if (negative) exponent = -exponent;
  }
  return leading + exponent >= 0;
}

}  // namespace

bool ParseFiniteDouble(std::string_view token, double* value) {
  const char* p = token.data();
  const char* const end = p + token.size();
  bool negative = false;
  if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
  const bool hex = end - p > 2 && p[0] == '0' && (p[1] == 'x' || p[1] == 'X');
  if (hex) p += 2;
  // Only a digit or a point may start the number: this refuses "inf",
  // "nan" and a second sign, which from_chars would take.
  if (p == end || !(IsDigit(*p, hex) || *p == '.')) return false;
  double v = 0.0;
  const auto [stop, error] = std::from_chars(
      p, end, v, hex ? std::chars_format::hex : std::chars_format::general);
  if (stop != end) return false;
  if (error == std::errc::result_out_of_range) {
    if (MagnitudeAtLeastOne(p, end, hex)) return false;
    v = 0.0;
  } else if (error != std::errc()) {
    return false;
  }
  if (!std::isfinite(v)) return false;
  *value = negative ? -v : v;
  return true;
}

bool ParseInt64(std::string_view token, int64_t* value) {
  const char* p = token.data();
  const char* const end = p + token.size();
  if (p < end && *p == '+') ++p;
  if (p == end || *p == '+') return false;
  int64_t v = 0;
  const auto [stop, error] = std::from_chars(p, end, v, 10);
  if (error != std::errc() || stop != end) return false;
  *value = v;
  return true;
}

std::string Quoted(std::string_view token) {
  constexpr size_t kMaxShown = 40;
  std::string out = "'";
  for (size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", c);
      out += hex;
    }
  }
  if (token.size() > kMaxShown) out += "...";
  return out + "'";
}

}  // namespace sdcb::mesh_parsing
