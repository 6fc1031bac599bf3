// A network of bicubic B-spline faces (converters/cad/cad_network.h) as one
// closed B-rep solid in a STEP (AP214) or IGES file, through OpenCASCADE:
// one Geom_BSplineSurface per face, one Geom_BSplineCurve per shared side;
// every face's boundary is its sides' curves, so the shell is assembled
// from the known topology (BRep_Builder: one vertex per corner, one edge
// per side, a straight pcurve in each of its two faces) instead of being
// sewn; the faces are counter-clockwise seen from outside, so the solid is
// oriented outward as built (its volume, MeasurePatchSet of the faces'
// Bezier spans, is positive); checked with BRepCheck_Analyzer; translated by
// STEPControl_Writer (AP214, written by StepData_StepWriter with every point
// once and 8 decimals) or IGESControl_Writer (B-rep mode), in millimetres:
// the poles' coordinates are taken as millimetres.
//
// This file (with its .cpp) is the only place of sdcb that includes
// OpenCASCADE.
#ifndef SDCB_CONVERTERS_CAD_CAD_FILE_H_
#define SDCB_CONVERTERS_CAD_CAD_FILE_H_

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdcb/converters/cad/cad_network.h"
#include "sdcb/core/common/progress.h"
#include "sdcb/core/common/status.h"

namespace sdcb {

enum class CadFormat { kStep, kIges };

struct CadSolidReport {
  int faces = 0;
  // Edges not shared by exactly two faces (0 for a closed shell) and the
  // tolerance of the vertices, edges and faces.
  int free_edges = 0;
  double tolerance = 0.0;
  bool valid = false;  // BRepCheck_Analyzer
  int64_t bytes = 0;   // of the file
  // MeasurePatchSet of the faces' Bezier spans, in their units.
  double volume = 0.0;
  double area = 0.0;
  struct Seconds {
    // Building the B-rep, BRepCheck_Analyzer, OpenCASCADE's STEP / IGES
    // translation and writer, the atomic write of the file.
    double build = 0.0, check = 0.0, translate = 0.0, write = 0.0;
  } seconds;
};

// Builds the solid from `network` (its faces, edges and vertices; any
// frame) and writes it to `path` atomically. Nothing is written, and a
// Status says why, when the faces do not close or the solid is not valid.
// `progress` (optional) is called with each stage's name ("checking",
// "translating", "writing") and the finished fraction in [0, 1].
StatusOr<CadSolidReport> WriteCadSolid(
    const CadNetwork& network, CadFormat format, const std::string& path,
    const ProgressCallback& progress = nullptr);

// The solids of several networks (one per closed part of a model) in one
// file: built and checked as WriteCadSolid does each, written as one
// compound of solids (STEP: one manifold solid B-rep each). The report adds
// faces, free edges, volumes, areas and seconds over the solids. One network
// writes exactly what WriteCadSolid writes.
StatusOr<CadSolidReport> WriteCadSolids(
    const std::vector<CadNetwork>& networks, CadFormat format,
    const std::string& path, const ProgressCallback& progress = nullptr);

// Process-wide: removes OpenCASCADE's default message printers (its writers
// print transfer statistics on stdout). For programs that own the process,
// like the command line; the library itself never calls it.
void SilenceOpenCascadeMessages();

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_CAD_FILE_H_
