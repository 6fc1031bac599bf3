// The `sdcb` command line: a thin dispatcher over the libraries.
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "tools/allocator_tuning.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/interrupts.h"

namespace {

// Before `sdcb fit`'s usage.
constexpr const char* kUsageHead = R"(usage: sdcb COMMAND [ARGS]

Turns closed genus-0 triangle meshes into one smooth spherical DCB-spline.

commands:
  check MESH [--json FILE] [--repair] [--max-parts N]
                             Report the mesh's topology, each part (connected
                             component) and self-intersections; exit 1 unless
                             sdcb can fit every part: manifold, consistently
                             oriented, genus 0, closed or open, with area and
                             no degenerate triangles. More than --max-parts
                             parts (default 1000, 0: no limit) is exit 1.
                             --repair first merges duplicate vertices, drops
                             degenerate and duplicate faces, orients the faces
                             and fills small holes, and says what it changed.
  param MESH -o SPHERE_MESH [--lambda L] [--json FILE] [--colors angle|area]
                             Map the mesh onto the unit sphere without folds
                             (same vertices and faces; .obj/.off/.ply);
                             lambda (default 1) trades angle for area
                             distortion; --colors angle|area needs .ply.
)";

// After `sdcb fit`'s usage (FitUsage()).
constexpr const char* kUsageTail = R"(  info MODEL.sdcb [--json FILE]
                             Summary of a model (format version, size,
                             quantization bound) and of each of its parts.
  dump MODEL.sdcb -o MODEL.json
                             Everything in a model, as JSON.
  eval MODEL.sdcb -i POINTS.txt -o VALUES.txt [--derivatives] [--part N]
                             Evaluate the surface (of part N, from 1;
                             default 1) at directions (x y z per
                             line, normalized onto the sphere); writes x y z
                             in the input's coordinates (+ unit normal).
                             A zero direction, or a model whose values are
                             not finite there, is an error: nothing written.
  compare MODEL.sdcb MESH [--json FILE] [--samples N] [--mesh-samples N]
          [--picture OUT.ply]
                             Two-sided distance between the surface and a
                             mesh (dense samples of both: N surface samples,
                             default 100000, and the mesh split to about N
                             mesh samples, default 100000, 0: its vertices;
                             an upper bound of the mesh's side's maximum),
                             folded area. --picture: the measured surface,
                             white (0) to red (its largest distance), folded
                             samples blue.

  export MODEL.sdcb -o OUT.{obj,ply,stl,gltf,glb} [--tolerance PCT]
      [--angle DEG] [--uniform N] [--draco [--qp BITS] [--cl LEVEL]]
      [--meshopt [--qp BITS]] [--colors none|error|curvature|gaussian]
      [--mesh MESH] [--json FILE] [--quiet] [--measure-samples N]
                             Triangulate the surface: adaptive (every
                             triangle within PCT, default 0.1, of the
                             surface and its normals within DEG, default
                             20) or --uniform (icosahedral, about N
                             vertices); glTF optionally Draco- or
                             meshopt-compressed (quantization from PCT
                             unless --qp); per-vertex colors (.ply/.gltf/
                             .glb): distance to --mesh, mean or Gaussian
                             curvature. The report's distance is measured
                             at N (default 4) random points per face. A
                             model whose fit measured folds: exit 1
                             unless --uniform. docs/EXPORT.md.
  export MODEL.sdcb -o OUT.{step,stp,igs,iges} [--tolerance PCT]
      [--smoothness-degrees DEG] [--max-faces N] [--max-control-points M]
      [--json FILE] [--quiet]
                             The surface as 384 bicubic B-spline faces in
                             one closed solid (STEP AP214 or IGES,
                             millimetres), C2 inside each face, within PCT
                             (default 0.05) of the surface, normals across
                             edges within DEG (default 0.5); exit 1, nothing
                             written, when M poles (default 200000) cannot
                             reach that or the model folds (unless DEG is
                             180). docs/CAD.md.

  batch MANIFEST [--jobs N] [--shard I/N] [--json-lines FILE]
      [--timeout SECONDS] [--force] [--quiet]
                             Convert every row "INPUT OUTPUT [OPTIONS]" of
                             the manifest (fit; export too when OUTPUT is
                             not .sdcb), each in its own processes: one JSON
                             line per row, failures isolated, finished
                             outputs skipped on a rerun; --shard I/N (else
                             Slurm's SLURM_ARRAY_TASK_ID/_COUNT, or
                             JOB_COMPLETION_INDEX with SDCB_SHARD_COUNT)
                             takes every N-th row. Exit 1 if any row failed.
                             docs/BATCH.md.
  cage MODEL.sdcb -o CAGE.{obj,fbx} [--scheme catmark|loop] [--faces N]
       [--tolerance PCT] [--json FILE] [--quiet]
                             Fit a subdivision cage (Catmull-Clark quads by
                             default, or Loop triangles) whose limit surface
                             follows the model's surface; refined until the
                             two-sided rms is within PCT (default 0.1) or the
                             cage would exceed N faces (default 20000).
                             .fbx (Catmull-Clark only) carries the creases
                             into Blender. docs/CAGE.md.

PCT values are percent of the largest side of the input's bounding box.

Meshes: .obj .off .ply .stl (ascii or binary). Commands that read a MESH
refuse files over --max-file-mb N (default 4096) and reads needing more than
--max-memory-mb N (default 8192, estimated before allocating).
Outputs are checked before any work and written atomically; an interrupted
run (SIGINT, SIGTERM, SIGHUP) leaves no temporary file.
'--json -' writes to stdout.
Exit codes: 0 success, 1 bad input (the reason is printed), 2 bad usage.
)";

// The usage text of every command.
std::string Usage() { return kUsageHead + sdcb::cli::FitUsage() + kUsageTail; }

}  // namespace

namespace {

int RunCommand(int argc, char** argv) {
  using namespace sdcb::cli;
  if (argc < 2) {
    std::cerr << Usage();
    return kExitUsage;
  }
  const std::string command = argv[1];
  if (command == "-h" || command == "--help" || command == "help") {
    std::cout << Usage();
    return kExitOk;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  for (const auto& a : args) {
    if (a == "-h" || a == "--help") {
      std::cout << Usage();
      return kExitOk;
    }
  }
  try {
    if (command == "check") return RunCheck(args);
    if (command == "param") return RunParam(args);
    if (command == "fit") return RunFit(args);
    if (command == "info") return RunInfo(args);
    if (command == "dump") return RunDump(args);
    if (command == "eval") return RunEval(args);
    if (command == "compare") return RunCompare(args);
    if (command == "export") return RunExport(args);
    if (command == "batch") return RunBatch(args);
    if (command == "cage") return RunCage(args);
    std::cerr << "sdcb: unknown command '" << command << "'\n\n" << Usage();
    return kExitUsage;
  } catch (const UsageError& e) {
    std::cerr << "sdcb " << command << ": " << e.message << "\n";
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    std::cerr << "sdcb " << command << ": out of memory\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "sdcb " << command << ": internal error: " << e.what() << "\n";
    return kExitBadInput;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Before any thread starts: the allocator's settings, and an interrupted
  // run removes its temporary output files.
  sdcb::cli::TuneAllocatorForRounds();
  sdcb::cli::InstallInterruptCleanup();
  const int code = RunCommand(argc, argv);
  sdcb::cli::EndRunBeforeAnyInterrupt();
  return code;
}
