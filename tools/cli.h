// Shared pieces of the `sdcb` command line: argument parsing, exit codes,
// reporting of library statuses.
#ifndef SDCB_TOOLS_CLI_H_
#define SDCB_TOOLS_CLI_H_

#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "sdcb/converters/gltf/gltf_import.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/mesh_parts.h"
#include "sdcb/core/mesh/self_intersections.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/mesh/vertex_welding.h"
#include "sdcb/core/spline/model.h"
#include "sdcb/io/mesh/mesh_reader.h"

namespace sdcb::cli {

// Exit codes of every subcommand (docs/CLI.md).
constexpr int kExitOk = 0;
constexpr int kExitBadInput = 1;  // unreadable / unusable input, failed write
constexpr int kExitUsage = 2;     // bad flags or arguments

// Thrown by the parser for a usage error; caught in main().
struct UsageError {
  std::string message;
};

// Parsed arguments: positionals in order, options by long name.
class Args {
 public:
  // `value_options` take a value ("--json FILE"); `flag_options` do not.
  Args(const std::vector<std::string>& argv,
       const std::vector<std::string>& value_options,
       const std::vector<std::string>& flag_options);

  const std::vector<std::string>& positionals() const { return positionals_; }
  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  std::string Get(const std::string& name,
                  const std::string& fallback = "") const;
  double GetDouble(const std::string& name, double fallback, double lo,
                   double hi) const;
  int GetInt(const std::string& name, int fallback, int lo, int hi) const;
  // GetInt of an option that may also be "auto": `auto_value` then (and
  // when absent, `fallback`); the message of a bad value names both forms.
  int GetIntOrAuto(const std::string& name, int fallback, int lo, int hi,
                   int auto_value) const;
  // Exactly `n` positionals, else a UsageError naming `what`.
  void RequirePositionals(size_t n, const std::string& what) const;

 private:
  std::vector<std::string> positionals_;
  std::map<std::string, std::string> values_;
};

// Prints "sdcb: <message>" on stderr and returns kExitBadInput.
int ReportError(const Status& status);

// Writes `text` to `path` atomically, or to stdout when `path` is "-".
Status WriteTextOutput(const std::string& path, const std::string& text);

// The extension of `path` in lower case, with its dot (".obj"), or "".
std::string LowercaseExtension(const std::string& path);

// Before any work: checks that each output can be written
// (io/common/atomic_file.h CheckWritableDestination; "" and "-" are skipped)
// and registers it so that an interrupted run leaves no temporary file
// (tools/interrupts.h).
Status PrepareOutputs(const std::vector<std::string>& paths);

// The options of every command that reads a MESH: "--max-file-mb N",
// "--max-memory-mb N" (MeshReadLimits) and the flag "--repair".
extern const std::vector<std::string> kMeshValueOptions;
extern const std::vector<std::string> kMeshFlagOptions;
// `a` followed by `b`, for building option lists.
std::vector<std::string> Concat(std::vector<std::string> a,
                                const std::vector<std::string>& b);

// The reading limits the mesh options ask for (defaults otherwise).
MeshReadLimits MeshReadLimitsFromArgs(const Args& args);

// With --repair: repairs `mesh` (core/mesh/mesh_repair.h) and prints what
// changed on stderr ("sdcb: PATH: repaired: ..."); a mesh that cannot be
// repaired is an error naming `path`. Without --repair: does nothing.
Status RepairIfAsked(const Args& args, const std::string& path,
                     TriangleMesh* mesh);

// "1 pair of triangles", "N pairs of triangles": how the commands name a
// count of intersecting pairs.
std::string IntersectingPairsText(long long pairs);

// Where a mesh turns back on itself: edges whose two triangles face opposite
// ways, their normals more than kTurnBackDegrees apart (a flap folded over
// its neighbours, a knife edge sharper than 30 degrees). A smooth surface
// that follows the mesh within a tolerance larger than the flap cannot turn
// there, so its normal opposes the flap's triangles: the fit measures that
// as a fold. Counted as the sharp edges of DetectFeatures at that angle.
inline constexpr double kTurnBackDegrees = 150.0;
long long CountTurnBackEdges(const TriangleMesh& mesh);

// "the input turns back on itself at N edges (...)": how the commands name
// a count of CountTurnBackEdges.
std::string TurnBackEdgesText(long long edges);

// Counts self-intersections (core/mesh/self_intersections.h) and prints a
// warning line on stderr when there are any. Returns the count, or -1 if
// the test was skipped (the reason goes to `skipped_because`).
long long WarnAboutSelfIntersections(const std::string& path,
                                     const TriangleMesh& mesh,
                                     std::string* skipped_because = nullptr);

// WarnAboutSelfIntersections for a report found already.
long long WarnAboutSelfIntersections(
    const std::string& path, const StatusOr<SelfIntersectionReport>& report,
    std::string* skipped_because = nullptr);

// Prints the reader's warnings on stderr ("sdcb: PATH: warning: ...").
void WarnAboutRead(const std::string& path, const MeshReadInfo& info);

// Without --repair (which merges equal positions itself): welds the
// vertices split at UV or normal seams when that is all it does
// (WeldSeams, core/mesh/vertex_welding.h) and prints what it merged, or,
// when the weld was declined, a warning naming --repair.
StatusOr<SeamWeldReport> WeldSeamsUnlessRepairing(const Args& args,
                                                  const std::string& path,
                                                  TriangleMesh* mesh);

// "16 vertices at the positions of others were left apart (merging them
// would make 2 edges non-manifold): --repair merges them".
std::string SeamsLeftApart(const SeamWeldReport& seams);

// A refusal of the mesh taken in, with the seams left apart named: "...;
// 16 vertices at the positions of others were left apart (merging them
// would make 2 edges non-manifold): --repair merges them". `refusal`
// unchanged when no weld was declined.
std::string WithSeamHint(const std::string& refusal,
                         const SeamWeldReport& seams);

// What the intake learned besides the mesh.
struct MeshIntakeNotes {
  MeshReadInfo read;
  SeamWeldReport seams;
};

// Where the faces of a mesh read from glTF came from: per face, the index of
// its primitive in `primitive_names` (GltfPrimitive::name). Empty for the
// other formats, and after --repair (which renumbers the faces).
struct MeshOrigin {
  std::vector<int> face_primitive;
  std::vector<std::string> primitive_names;
  // Per primitive, its glTF mesh and index in the mesh; the file's bytes.
  std::vector<std::array<int, 2>> primitive_ids;
  GltfDocument document;
  // Per primitive: its first face in the mesh, its material (-1 for none),
  // its per-corner TEXCOORD_0 and COLOR_0 and its faces' corners in the
  // file's vertex numbering (GltfPrimitive's source_corners).
  std::vector<int> primitive_first_face;
  std::vector<int> primitive_materials;
  std::vector<Eigen::MatrixX2d> primitive_texcoords;
  std::vector<Eigen::MatrixX4d> primitive_colors;
  std::vector<Eigen::MatrixX3i> primitive_source_corners;
};

// Any mesh file sdcb reads: .gltf / .glb through converters/gltf/
// gltf_import.h, every triangle primitive of the default scene in one mesh
// (ConcatenatePrimitives: mesh-local coordinates, primitives sharing no
// vertex), with a warning line on stderr for skipped points and lines
// primitives; the other formats through ReadMesh (`info` is theirs). Errors
// start with the path.
StatusOr<TriangleMesh> ReadInputMesh(const std::string& path,
                                     const MeshReadLimits& limits = {},
                                     MeshReadInfo* info = nullptr,
                                     MeshOrigin* origin = nullptr);

// The names of the parts (SplitIntoParts) of a mesh read with `origin`: the
// name of the primitive of a part's first face, with " (k)" appended (k =
// 1, 2, ... in part order) when that primitive has several parts. All ""
// when `origin` is empty.
std::vector<std::string> PartNames(const std::vector<MeshPart>& parts,
                                   const MeshOrigin& origin);

// The asset to keep with a model fitted from a glTF file (Model::asset,
// MakeGltfShell): every primitive with a fitted part becomes the parts
// whose first face it holds (PartNames' rule); a primitive all of whose
// parts were kept (ModelPart::kept) stays in the asset as the file had it.
// A primitive of fitted and kept parts is split (GltfFittedPrimitive::
// kept_corners): it keeps the kept parts' triangles as the file had them,
// and a primitive appended to its mesh holds the fitted parts; when its
// vertices are Draco- or meshopt-compressed (no source_corners) it holds
// all its parts instead, the kept ones written as their triangles.
// A primitive holding parts whose material has a base colour texture, or
// which has COLOR_0, gets an atlas baked from its parts' maps to the
// sphere (`model_parts[i].spline.parameters` for parts[i]; none when a
// part's parameters were not kept or it was kept, or with a sentence in
// `warnings` when its texture does not load). "" when `origin` is empty.
StatusOr<std::string> KeptGltfAsset(const std::vector<MeshPart>& parts,
                                    const std::vector<ModelPart>& model_parts,
                                    const MeshOrigin& origin,
                                    std::vector<std::string>* warnings);

// What `check`, `param` and `fit` read: the MESH with the limits of the
// options (warnings printed), repaired if asked, else, unless it is glTF
// (whose primitives are merged by position as read), its seams welded; its
// parts are checked by the caller (core/mesh/mesh_parts.h,
// core/fit/fit_model.h). `origin` as ReadInputMesh's (empty after
// --repair).
StatusOr<TriangleMesh> ReadMeshToFit(const Args& args, const std::string& path,
                                     MeshIntakeNotes* notes = nullptr,
                                     MeshOrigin* origin = nullptr);

// What `param` reads: the MESH with the limits of the options,
// repaired if asked, checked to be closed genus 0 (one sentence naming
// `path` otherwise). Not checked for self-intersections.
StatusOr<TriangleMesh> ReadFittableMesh(const Args& args,
                                        const std::string& path);

// The self-intersection test of every part, summed: pairs of triangles of
// different parts are not counted (parts are fitted apart). Skipped when a
// part's test is. Each part gets the share of the whole mesh's budget of
// box pairs that its triangles are of the mesh's (`total_faces`), so that
// the parts together test no more pairs than one mesh of their size could.
StatusOr<SelfIntersectionReport> PartsSelfIntersections(
    const std::vector<MeshPart>& parts, int total_faces);

// The self-intersection search of a mesh (which must outlive this) run on a
// thread of its own at the lowest CPU priority (nice 19) and on that thread
// alone: beside the work that needs the mesh, it takes the cycles that work
// leaves idle, and it adds none when the work keeps every core busy. The
// report is the same as FindSelfIntersections'.
class SelfIntersectionsBeside {
 public:
  explicit SelfIntersectionsBeside(const TriangleMesh& mesh);
  // PartsSelfIntersections(parts, total_faces) the same way (`parts` must
  // outlive this): for a glTF input, whose primitives are in their own
  // local frames, pairs of different parts mean nothing.
  SelfIntersectionsBeside(const std::vector<MeshPart>& parts, int total_faces);
  SelfIntersectionsBeside(const SelfIntersectionsBeside&) = delete;
  SelfIntersectionsBeside& operator=(const SelfIntersectionsBeside&) = delete;
  ~SelfIntersectionsBeside();  // waits for the search

  // Waits for the search and returns WarnAboutSelfIntersections(path, ...):
  // the warning printed, the count of intersecting pairs (-1 if skipped).
  long long Warn(const std::string& path);

 private:
  explicit SelfIntersectionsBeside(
      std::function<StatusOr<SelfIntersectionReport>()> search);

  std::optional<StatusOr<SelfIntersectionReport>> report_;
  std::thread thread_;
};

}  // namespace sdcb::cli

#endif  // SDCB_TOOLS_CLI_H_
