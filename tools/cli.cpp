#include "tools/cli.h"

#include <sys/resource.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>

#include "sdcb/converters/gltf/gltf_asset.h"
#include "sdcb/converters/gltf/gltf_import.h"
#include "sdcb/converters/gltf/texture_bake.h"
#include "sdcb/core/mesh/feature_curves.h"
#include "sdcb/core/mesh/mesh_repair.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/mesh/self_intersections.h"
#include "sdcb/io/common/atomic_file.h"
#include "tools/commands.h"
#include "tools/interrupts.h"

namespace sdcb::cli {

Args::Args(const std::vector<std::string>& argv,
           const std::vector<std::string>& value_options,
           const std::vector<std::string>& flag_options) {
  auto contains = [](const std::vector<std::string>& list,
                     const std::string& s) {
    for (const auto& x : list) {
      if (x == s) return true;
    }
    return false;
  };
  for (size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
      std::string name = a.substr(2), value;
      const size_t eq = name.find('=');
      const bool inline_value = eq != std::string::npos;
      if (inline_value) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
      if (contains(flag_options, name)) {
        if (inline_value)
          throw UsageError{"option --" + name + " takes no value"};
        values_[name] = "1";
      } else if (contains(value_options, name)) {
        if (!inline_value) {
          if (i + 1 >= argv.size()) {
            throw UsageError{"option --" + name + " needs a value"};
          }
          value = argv[++i];
        }
        values_[name] = value;
      } else {
        throw UsageError{"unknown option '" + a + "'"};
      }
    } else if (a.size() > 1 && a[0] == '-' && a != "-") {
      if (a == "-o" || a == "-i") {
        if (i + 1 >= argv.size())
          throw UsageError{"option " + a + " needs a value"};
        values_[a == "-o" ? "output" : "input"] = argv[++i];
      } else {
        throw UsageError{"unknown option '" + a + "'"};
      }
    } else {
      positionals_.push_back(a);
    }
  }
}

std::string Args::Get(const std::string& name,
                      const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

double Args::GetDouble(const std::string& name, double fallback, double lo,
                       double hi) const {
  auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end != '\0' || !std::isfinite(v) || v < lo ||
      v > hi) {
    throw UsageError{"--" + name + " must be a number in [" +
                     std::to_string(lo) + ", " + std::to_string(hi) +
                     "], got '" + it->second + "'"};
  }
  return v;
}

namespace {

// The value of --name as an integer in [lo, hi], else a UsageError that
// names what it accepts (`also`: another accepted form, or "").
int ParseIntOption(const std::string& name, const std::string& value, int lo,
                   int hi, const std::string& also) {
  char* end = nullptr;
  const long v = std::strtol(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || v < lo || v > hi) {
    throw UsageError{"--" + name + " must be an integer in [" +
                     std::to_string(lo) + ", " + std::to_string(hi) + "]" +
                     also + ", got '" + value + "'"};
  }
  return static_cast<int>(v);
}

}  // namespace

int Args::GetInt(const std::string& name, int fallback, int lo, int hi) const {
  auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  return ParseIntOption(name, it->second, lo, hi, "");
}

int Args::GetIntOrAuto(const std::string& name, int fallback, int lo, int hi,
                       int auto_value) const {
  auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  if (it->second == "auto") return auto_value;
  return ParseIntOption(name, it->second, lo, hi, " or auto");
}

void Args::RequirePositionals(size_t n, const std::string& what) const {
  if (positionals_.size() < n) throw UsageError{"missing " + what};
  if (positionals_.size() > n) {
    throw UsageError{"unexpected argument '" + positionals_[n] + "'"};
  }
}

int ReportError(const Status& status) {
  std::cerr << "sdcb: " << status.message() << "\n";
  return kExitBadInput;
}

Status WriteTextOutput(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::cout << text;
    std::cout.flush();
    return std::cout ? Status::Ok()
                     : IoError("writing to standard output failed");
  }
  return WriteFileAtomically(text, path);
}

std::string LowercaseExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

Status PrepareOutputs(const std::vector<std::string>& paths) {
  for (const std::string& path : paths) {
    if (path.empty() || path == "-") continue;
    // Registered first: the check itself creates a temporary file.
    RemoveTemporariesOnInterrupt(path);
    SDCB_RETURN_IF_ERROR(CheckWritableDestination(path));
  }
  return Status::Ok();
}

const std::vector<std::string> kMeshValueOptions = {"max-file-mb",
                                                    "max-memory-mb"};
const std::vector<std::string> kMeshFlagOptions = {"repair"};

std::vector<std::string> Concat(std::vector<std::string> a,
                                const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

CommandOptions OptionNamesOf(const std::vector<OptionSpec>& specs) {
  CommandOptions names;
  for (const OptionSpec& spec : specs) {
    (spec.value.empty() ? names.flags : names.values).push_back(spec.name);
  }
  return names;
}

std::string OptionUsage(const std::vector<OptionSpec>& specs) {
  constexpr size_t kHelpColumn = 29, kWidth = 79;
  std::string text;
  for (const OptionSpec& spec : specs) {
    std::string line = "      --" + spec.name;
    if (!spec.value.empty()) line += " " + spec.value;
    // The help's words, wrapped; it starts on the next line when the
    // option's own text reaches its column.
    if (line.size() + 1 > kHelpColumn) {
      text += line + "\n";
      line.clear();
    }
    size_t start = 0;
    while (start < spec.help.size()) {
      size_t end = spec.help.find(' ', start);
      if (end == std::string::npos) end = spec.help.size();
      const std::string word = spec.help.substr(start, end - start);
      start = end + 1;
      const bool first = line.size() <= kHelpColumn;
      if (!first && line.size() + 1 + word.size() > kWidth) {
        text += line + "\n";
        line.clear();
      }
      if (line.size() < kHelpColumn) {
        line.resize(kHelpColumn, ' ');
      } else {
        line += ' ';
      }
      line += word;
    }
    text += line + "\n";
  }
  return text;
}

MeshReadLimits MeshReadLimitsFromArgs(const Args& args) {
  MeshReadLimits limits;
  constexpr int kMaxMb = 1 << 30;  // a petabyte
  limits.max_file_bytes =
      int64_t{args.GetInt("max-file-mb",
                          static_cast<int>(limits.max_file_bytes >> 20), 1,
                          kMaxMb)}
      << 20;
  limits.max_memory_bytes =
      int64_t{args.GetInt("max-memory-mb",
                          static_cast<int>(limits.max_memory_bytes >> 20), 1,
                          kMaxMb)}
      << 20;
  return limits;
}

Status RepairIfAsked(const Args& args, const std::string& path,
                     TriangleMesh* mesh) {
  if (!args.Has("repair")) return Status::Ok();
  MeshRepairReport report;
  StatusOr<TriangleMesh> repaired = RepairMesh(*mesh, {}, &report);
  if (!repaired.ok()) {
    return repaired.status().WithPrefix(path);
  }
  *mesh = std::move(repaired).value();
  std::cerr << "sdcb: " << path << ": repaired: " << report.Describe() << "\n";
  return Status::Ok();
}

std::string IntersectingPairsText(long long pairs) {
  return std::to_string(pairs) + (pairs == 1 ? " pair" : " pairs") +
         " of triangles";
}

long long CountTurnBackEdges(const TriangleMesh& mesh) {
  const StatusOr<MeshFeatures> turns = DetectFeatures(mesh, kTurnBackDegrees);
  return turns.ok() ? static_cast<long long>(turns->edges.size()) : 0;
}

std::string TurnBackEdgesText(long long edges) {
  return "the input turns back on itself at " + std::to_string(edges) +
         (edges == 1 ? " edge" : " edges") +
         " (neighbouring triangles face opposite ways)";
}

long long WarnAboutSelfIntersections(const std::string& path,
                                     const TriangleMesh& mesh,
                                     std::string* skipped_because) {
  return WarnAboutSelfIntersections(path, FindSelfIntersections(mesh),
                                    skipped_because);
}

long long WarnAboutSelfIntersections(
    const std::string& path, const StatusOr<SelfIntersectionReport>& report,
    std::string* skipped_because) {
  if (!report.ok() || !report->checked) {
    if (skipped_because != nullptr) {
      *skipped_because =
          report.ok() ? report->skipped_because : report.status().message();
    }
    return -1;
  }
  if (report->intersecting_pairs > 0) {
    std::cerr << "sdcb: " << path << ": warning: "
              << IntersectingPairsText(report->intersecting_pairs)
              << " intersect (the surface passes through itself; a fitted "
                 "surface would too)\n";
  }
  return report->intersecting_pairs;
}

void WarnAboutRead(const std::string& path, const MeshReadInfo& info) {
  for (const std::string& warning : info.warnings) {
    std::cerr << "sdcb: " << path << ": warning: " << warning << "\n";
  }
}

StatusOr<SeamWeldReport> WeldSeamsUnlessRepairing(const Args& args,
                                                  const std::string& path,
                                                  TriangleMesh* mesh) {
  SeamWeldReport seams;
  if (args.Has("repair")) return seams;
  StatusOr<WeldedMesh> welded = WeldSeams(*mesh, &seams);
  if (!welded.ok()) return welded.status().WithPrefix(path);
  if (seams.merged_vertices > 0) {
    *mesh = std::move(welded->mesh);
    std::cerr << "sdcb: " << path << ": " << seams.Describe() << "\n";
  } else if (seams.declined_vertices > 0) {
    std::cerr << "sdcb: " << path << ": warning: " << SeamsLeftApart(seams)
              << "\n";
  }
  return seams;
}

std::string SeamsLeftApart(const SeamWeldReport& seams) {
  const int n = seams.declined_vertices;
  return std::to_string(n) +
         (n == 1 ? " vertex at the position of another was"
                 : " vertices at the positions of others were") +
         " left apart (" + seams.declined_because + "): --repair merges them";
}

std::string WithSeamHint(const std::string& refusal,
                         const SeamWeldReport& seams) {
  if (seams.declined_vertices == 0 || refusal.empty()) return refusal;
  return refusal + "; " + SeamsLeftApart(seams);
}

StatusOr<TriangleMesh> ReadInputMesh(const std::string& path,
                                     const MeshReadLimits& limits,
                                     MeshReadInfo* info, MeshOrigin* origin) {
  if (!IsGltfPath(path)) {
    if (!MeshFileFormatFromPath(path).ok()) {
      const std::string ext = std::filesystem::path(path).extension().string();
      return UnsupportedError("unknown mesh format '" + ext +
                              "' (sdcb reads .obj, .off, .ply, .stl, .gltf "
                              "and .glb)")
          .WithPrefix(path);
    }
    return ReadMesh(path, info, limits);
  }
  SDCB_ASSIGN_OR_RETURN(GltfAsset asset, ReadGltf(path, limits));
  if (asset.point_primitives + asset.line_primitives > 0) {
    std::cerr << "sdcb: " << path << ": warning: skipped "
              << asset.point_primitives << " points and "
              << asset.line_primitives
              << " lines primitives (sdcb fits triangles)\n";
  }
  std::vector<int> face_primitive;
  TriangleMesh mesh = ConcatenatePrimitives(asset, &face_primitive);
  if (origin != nullptr) {
    origin->face_primitive = std::move(face_primitive);
    origin->primitive_names.clear();
    origin->primitive_ids.clear();
    origin->primitive_first_face.clear();
    origin->primitive_materials.clear();
    origin->primitive_texcoords.clear();
    origin->primitive_colors.clear();
    origin->primitive_source_corners.clear();
    int first_face = 0;
    for (GltfPrimitive& p : asset.primitives) {
      origin->primitive_names.push_back(p.name);
      origin->primitive_ids.push_back({p.mesh, p.primitive});
      origin->primitive_first_face.push_back(first_face);
      first_face += p.triangles.num_faces();
      origin->primitive_materials.push_back(p.material);
      origin->primitive_texcoords.push_back(std::move(p.texcoords));
      origin->primitive_colors.push_back(std::move(p.colors));
      origin->primitive_source_corners.push_back(std::move(p.source_corners));
    }
    origin->document = std::move(asset.document);
  }
  return mesh;
}

namespace {

// What BakeCubeAtlas needs of input part `part` of primitive `p`: its
// vertices' sphere points, its faces, their corners' texture coordinates
// and colours.
TextureBakePart BakePartOf(const MeshPart& part, const ModelPart& fitted,
                           const MeshOrigin& origin, int p) {
  TextureBakePart out;
  out.sphere_points =
      fitted.spline.parameters.topRows(part.mesh.num_vertices());
  out.faces = part.mesh.faces;
  const Eigen::MatrixX2d& uv = origin.primitive_texcoords[p];
  const Eigen::MatrixX4d& rgba = origin.primitive_colors[p];
  const Eigen::Index corners = 3 * part.mesh.num_faces();
  out.texcoords.resize(uv.rows() > 0 ? corners : 0, 2);
  out.colors.resize(rgba.rows() > 0 ? corners : 0, 4);
  for (size_t f = 0; f < part.input_faces.size(); ++f) {
    const int local = part.input_faces[f] - origin.primitive_first_face[p];
    for (int k = 0; k < 3; ++k) {
      if (uv.rows() > 0) out.texcoords.row(3 * f + k) = uv.row(3 * local + k);
      if (rgba.rows() > 0) out.colors.row(3 * f + k) = rgba.row(3 * local + k);
    }
  }
  return out;
}

// Bakes the atlas of fitted primitive `f` (index p) when its material has
// a base colour texture or it has colours; leaves it without one when a
// part's map was not kept.
Status BakeAtlas(const std::vector<MeshPart>& parts,
                 const std::vector<ModelPart>& fitted, const MeshOrigin& origin,
                 int p, GltfFittedPrimitive* f,
                 std::vector<std::string>* warnings) {
  StatusOr<GltfTexture> loaded =
      LoadBaseColorTexture(origin.document, origin.primitive_materials[p]);
  if (!loaded.ok()) {
    warnings->push_back("primitive \"" + origin.primitive_names[p] +
                        "\": " + loaded.status().message() +
                        "; its fitted surface is written without its texture");
    return Status::Ok();
  }
  const GltfTexture& texture = *loaded;
  const bool textured =
      texture.width > 0 && origin.primitive_texcoords[p].rows() > 0;
  if (!textured && origin.primitive_colors[p].rows() == 0) return Status::Ok();
  std::vector<TextureBakePart> bake;
  for (const int i : f->parts) {
    if (fitted[i].spline.parameters.rows() < parts[i].mesh.num_vertices()) {
      return Status::Ok();
    }
    bake.push_back(BakePartOf(parts[i], fitted[i], origin, p));
  }
  SDCB_ASSIGN_OR_RETURN(BakedAtlas atlas, BakeCubeAtlas(bake, texture));
  f->atlas_png = std::move(atlas.png);
  f->atlas_layout = atlas.layout;
  return Status::Ok();
}

// The triangles of `kept` (parts of primitive `p`) in the file's vertex
// numbering, in the file's order.
Eigen::MatrixX3i KeptCorners(const std::vector<MeshPart>& parts,
                             const std::vector<int>& kept,
                             const MeshOrigin& origin, int p) {
  std::vector<int> faces;
  for (const int i : kept) {
    for (const int face : parts[i].input_faces) {
      faces.push_back(face - origin.primitive_first_face[p]);
    }
  }
  std::sort(faces.begin(), faces.end());
  const Eigen::MatrixX3i& corners = origin.primitive_source_corners[p];
  Eigen::MatrixX3i out(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) {
    out.row(static_cast<Eigen::Index>(f)) = corners.row(faces[f]);
  }
  return out;
}

}  // namespace

StatusOr<std::string> KeptGltfAsset(const std::vector<MeshPart>& parts,
                                    const std::vector<ModelPart>& model_parts,
                                    const MeshOrigin& origin,
                                    std::vector<std::string>* warnings) {
  if (origin.face_primitive.empty()) return std::string();
  const size_t num_primitives = origin.primitive_ids.size();
  // Per primitive, the parts whose first face it holds: fitted, kept.
  std::vector<std::vector<int>> fitted_of(num_primitives),
      kept_of(num_primitives);
  for (size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].input_faces.empty()) continue;
    const int p = origin.face_primitive[parts[i].input_faces[0]];
    const bool is_fitted = i < model_parts.size() && !model_parts[i].kept;
    (is_fitted ? fitted_of : kept_of)[p].push_back(static_cast<int>(i));
  }
  std::vector<GltfFittedPrimitive> fitted;
  for (size_t p = 0; p < num_primitives; ++p) {
    if (fitted_of[p].empty()) continue;
    GltfFittedPrimitive f;
    f.mesh = origin.primitive_ids[p][0];
    f.primitive = origin.primitive_ids[p][1];
    f.parts = fitted_of[p];
    if (!kept_of[p].empty()) {
      if (origin.primitive_source_corners[p].rows() > 0) {
        f.kept_corners =
            KeptCorners(parts, kept_of[p], origin, static_cast<int>(p));
      } else {
        // Compressed: the primitive holds its kept parts too, in part order.
        f.parts.insert(f.parts.end(), kept_of[p].begin(), kept_of[p].end());
        std::sort(f.parts.begin(), f.parts.end());
      }
    }
    if (model_parts.size() == parts.size()) {
      SDCB_RETURN_IF_ERROR(BakeAtlas(parts, model_parts, origin,
                                     static_cast<int>(p), &f, warnings));
    }
    fitted.push_back(std::move(f));
  }
  return MakeGltfShell(origin.document, fitted);
}

std::vector<std::string> PartNames(const std::vector<MeshPart>& parts,
                                   const MeshOrigin& origin) {
  std::vector<std::string> names(parts.size());
  if (origin.face_primitive.empty()) return names;
  std::vector<int> primitive(parts.size(), -1);
  std::vector<int> parts_of(origin.primitive_names.size(), 0);
  for (size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].input_faces.empty()) continue;
    primitive[i] = origin.face_primitive[parts[i].input_faces[0]];
    ++parts_of[primitive[i]];
  }
  std::vector<int> seen(origin.primitive_names.size(), 0);
  for (size_t i = 0; i < parts.size(); ++i) {
    if (primitive[i] < 0) continue;
    names[i] = origin.primitive_names[primitive[i]];
    if (parts_of[primitive[i]] > 1) {
      names[i] += " (" + std::to_string(++seen[primitive[i]]) + ")";
    }
  }
  return names;
}

StatusOr<TriangleMesh> ReadMeshToFit(const Args& args, const std::string& path,
                                     MeshIntakeNotes* notes,
                                     MeshOrigin* origin) {
  MeshIntakeNotes local;
  MeshIntakeNotes* n = notes != nullptr ? notes : &local;
  SDCB_ASSIGN_OR_RETURN(
      TriangleMesh mesh,
      ReadInputMesh(path, MeshReadLimitsFromArgs(args), &n->read, origin));
  WarnAboutRead(path, n->read);
  SDCB_RETURN_IF_ERROR(RepairIfAsked(args, path, &mesh));
  if (origin != nullptr && args.Has("repair")) *origin = MeshOrigin();
  // A glTF primitive's vertices are merged by position already; welding
  // across primitives would join parts that belong to two of them.
  if (!IsGltfPath(path)) {
    SDCB_ASSIGN_OR_RETURN(n->seams,
                          WeldSeamsUnlessRepairing(args, path, &mesh));
  }
  return mesh;
}

StatusOr<TriangleMesh> ReadFittableMesh(const Args& args,
                                        const std::string& path) {
  SDCB_ASSIGN_OR_RETURN(TriangleMesh mesh, ReadMeshToFit(args, path));
  SDCB_RETURN_IF_ERROR(RequireClosedGenusZero(mesh).WithPrefix(path));
  return mesh;
}

StatusOr<SelfIntersectionReport> PartsSelfIntersections(
    const std::vector<MeshPart>& parts, int total_faces) {
  const SelfIntersectionOptions whole;
  SelfIntersectionReport total;
  total.checked = true;
  for (const MeshPart& part : parts) {
    SelfIntersectionOptions share = whole;
    share.max_extra_pairs =
        whole.max_extra_pairs * part.mesh.num_faces() / total_faces;
    SDCB_ASSIGN_OR_RETURN(const SelfIntersectionReport one,
                          FindSelfIntersections(part.mesh, share));
    if (!one.checked) return one;
    total.intersecting_pairs += one.intersecting_pairs;
  }
  return total;
}

SelfIntersectionsBeside::SelfIntersectionsBeside(const TriangleMesh& mesh)
    : SelfIntersectionsBeside([&mesh] { return FindSelfIntersections(mesh); }) {
}

SelfIntersectionsBeside::SelfIntersectionsBeside(
    const std::vector<MeshPart>& parts, int total_faces)
    : SelfIntersectionsBeside([&parts, total_faces] {
        return PartsSelfIntersections(parts, total_faces);
      }) {}

SelfIntersectionsBeside::SelfIntersectionsBeside(
    std::function<StatusOr<SelfIntersectionReport>()> search)
    : thread_([this, search = std::move(search)] {
        // This thread's own nice value (Linux: per thread); lowering it
        // needs no privilege. Failing, the search runs at the usual one.
        setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 19);
        // One slot and no workers: the search runs on this thread only.
        tbb::task_arena alone(1, 1);
        try {
          alone.execute([&] { report_.emplace(search()); });
        } catch (const std::exception& e) {
          // Out of memory here is not the work's end: the search is skipped.
          report_.emplace(
              InternalError(std::string("not searched: ") + e.what()));
        }
      }) {}

SelfIntersectionsBeside::~SelfIntersectionsBeside() {
  if (thread_.joinable()) thread_.join();
}

long long SelfIntersectionsBeside::Warn(const std::string& path) {
  if (thread_.joinable()) thread_.join();
  return WarnAboutSelfIntersections(path, *report_);
}

}  // namespace sdcb::cli
