// The `sdcb` command line: a thin dispatcher over the libraries.
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "tools/cli.h"
#include "tools/commands.h"

namespace {

constexpr const char* kUsage = R"(usage: sdcb COMMAND [ARGS]

Turns closed genus-0 triangle meshes into one smooth spherical DCB-spline.

commands:
  check MESH [--json FILE]   Report the mesh's topology; exit 1 unless it is a
                             closed, manifold, single-component genus-0 mesh.
  param MESH -o SPHERE_MESH [--lambda L] [--json FILE] [--colors angle|area]
                             Map the mesh onto the unit sphere without folds
                             (same vertices and faces; .obj/.off/.ply);
                             lambda (default 1) trades angle for area
                             distortion; --colors angle|area needs .ply.
  fit MESH -o MODEL.sdcb [--degree K] [--rmse PCT] [--knots-per-round N]
      [--max-rounds R] [--max-control-points M] [--lambda L] [--threads T]
      [--regularization R] [--store-parameters] [--quantize BITS]
      [--json FILE] [--plot FILE.svg] [--quiet]
                             Fit one smooth spherical DCB-spline (defaults:
                             degree 4, rmse 0.05 %, 100 knots per round, 30
                             rounds); --plot draws the error per round;
                             --store-parameters keeps each vertex's sphere
                             point; --quantize BITS (8..30) stores the control
                             points in BITS bits, the error bound reported.
  info MODEL.sdcb [--json FILE]
                             Summary of a model (format version, size,
                             quantization bound).
  dump MODEL.sdcb -o MODEL.json
                             Everything in a model, as JSON.
  eval MODEL.sdcb -i POINTS.txt -o VALUES.txt [--derivatives]
                             Evaluate the surface at directions (x y z per
                             line, normalized onto the sphere); writes x y z
                             in the input's coordinates (+ unit normal).
  compare MODEL.sdcb MESH [--json FILE] [--samples N]
                             Two-sided distance between the surface and a
                             mesh (dense samples of both), folded area.
  cage MODEL.sdcb -o CAGE.obj [--scheme catmark|loop] [--faces N]
       [--tolerance PCT] [--json FILE] [--quiet]
                             Fit a subdivision cage (Catmull-Clark quads by
                             default, or Loop triangles) whose limit surface
                             follows the model's surface; refined until the
                             two-sided rms is within PCT (default 0.1) or the
                             cage would exceed N faces (default 20000).

PCT values are percent of the largest side of the input's bounding box.

Meshes: .obj .off .ply .stl (ascii or binary). '--json -' writes to stdout.
Exit codes: 0 success, 1 bad input (the reason is printed), 2 bad usage.
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace sdcb::cli;
  if (argc < 2) {
    std::cerr << kUsage;
    return kExitUsage;
  }
  const std::string command = argv[1];
  if (command == "-h" || command == "--help" || command == "help") {
    std::cout << kUsage;
    return kExitOk;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  for (const auto& a : args) {
    if (a == "-h" || a == "--help") {
      std::cout << kUsage;
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
    if (command == "cage") return RunCage(args);
    std::cerr << "sdcb: unknown command '" << command << "'\n\n" << kUsage;
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
