#include "sdcb/converters/cad_file.h"

#include <BRepCheck_Analyzer.hxx>
#include <BRep_Builder.hxx>
#include <Geom2d_Line.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Precision.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

#include "sdcb/converters/stopwatch.h"
#include "sdcb/io/atomic_file.h"

namespace sdcb {
namespace {

// The knot vector of one cubic Bezier span: knots 0 and 1, each of
// multiplicity 4.
struct BezierKnots {
  TColStd_Array1OfReal knots{1, 2};
  TColStd_Array1OfInteger multiplicities{1, 2};
  BezierKnots() {
    knots.SetValue(1, 0.0);
    knots.SetValue(2, 1.0);
    multiplicities.SetValue(1, 4);
    multiplicities.SetValue(2, 4);
  }
};

Handle(Geom_BSplineSurface) MakeSurface(const BicubicPatch& patch) {
  TColgp_Array2OfPnt poles(1, 4, 1, 4);
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector3d& p = patch.poles[4 * j + i];
      poles.SetValue(i + 1, j + 1, gp_Pnt(p.x(), p.y(), p.z()));
    }
  }
  const BezierKnots span;
  return new Geom_BSplineSurface(poles, span.knots, span.knots,
                                 span.multiplicities, span.multiplicities, 3,
                                 3);
}

// Writes `shape` with OpenCASCADE's writer into `contents`, through a
// temporary file next to `path` (STEPControl_Writer writes files only).
Status WriteStep(const TopoDS_Shape& solid, const std::string& path,
                 std::string* contents) {
  STEPControl_Writer writer;
  if (writer.Transfer(solid, STEPControl_ManifoldSolidBrep) !=
      IFSelect_RetDone) {
    return InternalError(path +
                         ": OpenCASCADE could not translate the solid "
                         "to STEP");
  }
  const std::string temporary = TemporaryFilePrefix(path) + "occt";
  const IFSelect_ReturnStatus written = writer.Write(temporary.c_str());
  std::ifstream in(temporary, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  in.close();
  std::error_code ignored;
  std::filesystem::remove(temporary, ignored);
  if (written != IFSelect_RetDone || buffer.str().empty()) {
    return IoError(path + ": OpenCASCADE could not write the STEP file");
  }
  *contents = buffer.str();
  return Status::Ok();
}

Status WriteIges(const TopoDS_Shape& solid, const std::string& path,
                 std::string* contents) {
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 1);  // 1: B-rep (solids, shells, faces)
  if (!writer.AddShape(solid)) {
    return InternalError(path +
                         ": OpenCASCADE could not translate the solid "
                         "to IGES");
  }
  writer.ComputeModel();
  std::ostringstream buffer;
  if (!writer.Write(buffer) || buffer.str().empty()) {
    return IoError(path + ": OpenCASCADE could not write the IGES file");
  }
  *contents = buffer.str();
  return Status::Ok();
}

}  // namespace

StatusOr<CadSolidReport> WriteCadSolid(
    const std::vector<BicubicPatch>& patches,
    const std::vector<std::array<int, 4>>& corners, CadFormat format,
    const std::string& path,
    const std::function<void(const std::string& stage, double fraction)>&
        progress) {
  const auto stage = [&](const char* name, double fraction) {
    if (progress) progress(name, fraction);
  };
  if (patches.empty() || patches.size() != corners.size()) {
    return InvalidArgumentError(path +
                                ": no patches, or not one corner "
                                "quadruple per patch");
  }
  CadSolidReport report;
  Stopwatch t0;
  // The patches are counter-clockwise seen from outside, so the solid is
  // oriented outward as built; its volume says so.
  const PatchSetMeasures measures = MeasurePatchSet(patches);
  report.volume = measures.volume;
  report.area = measures.area;
  std::string contents;
  try {
    // The patches meet pole for pole, so the shared edges are known: the
    // shell is built topologically (one vertex per layout vertex, one edge
    // per layout edge, its 3D curve the patches' common boundary and a
    // straight pcurve in each of its two faces), not sewn.
    report.tolerance = Precision::Confusion();
    const double tolerance = report.tolerance;
    BRep_Builder builder;
    std::unordered_map<int, TopoDS_Vertex> vertices;
    const auto vertex = [&](int index, const Eigen::Vector3d& p) {
      auto [it, inserted] = vertices.try_emplace(index);
      if (inserted) {
        builder.MakeVertex(it->second, gp_Pnt(p.x(), p.y(), p.z()), tolerance);
      }
      return it->second;
    };
    // Edges keyed by (lower, higher) vertex; parameter 0 at the lower.
    std::map<std::pair<int, int>, std::pair<TopoDS_Edge, int>> edges;
    TopoDS_Shell shell;
    builder.MakeShell(shell);
    constexpr int kSlots[4][4] = {
        {0, 1, 2, 3}, {3, 7, 11, 15}, {15, 14, 13, 12}, {12, 8, 4, 0}};
    for (size_t f = 0; f < patches.size(); ++f) {
      const BicubicPatch& patch = patches[f];
      TopoDS_Face face;
      builder.MakeFace(face, MakeSurface(patch), tolerance);
      TopoDS_Wire wire;
      builder.MakeWire(wire);
      for (int k = 0; k < 4; ++k) {
        const int a = corners[f][k], b = corners[f][(k + 1) % 4];
        const bool forward = a < b;
        auto [it, inserted] =
            edges.try_emplace({std::min(a, b), std::max(a, b)});
        TopoDS_Edge& edge = it->second.first;
        if (inserted) {
          TColgp_Array1OfPnt poles(1, 4);
          for (int q = 0; q < 4; ++q) {
            const Eigen::Vector3d& p =
                patch.poles[kSlots[k][forward ? q : 3 - q]];
            poles.SetValue(q + 1, gp_Pnt(p.x(), p.y(), p.z()));
          }
          const BezierKnots span;
          builder.MakeEdge(
              edge,
              new Geom_BSplineCurve(poles, span.knots, span.multiplicities, 3),
              tolerance);
          const int lo = std::min(a, b), hi = std::max(a, b);
          builder.Add(edge, vertex(lo, patch.poles[kSlots[k][forward ? 0 : 3]])
                                .Oriented(TopAbs_FORWARD));
          builder.Add(edge, vertex(hi, patch.poles[kSlots[k][forward ? 3 : 0]])
                                .Oriented(TopAbs_REVERSED));
          builder.Range(edge, 0.0, 1.0);
        }
        ++it->second.second;
        // The pcurve: the side of the unit square, in the edge's parameter.
        const Eigen::Vector2d p0 = QuadEdgeParameter(k, forward ? 0.0 : 1.0);
        const Eigen::Vector2d p1 = QuadEdgeParameter(k, forward ? 1.0 : 0.0);
        builder.UpdateEdge(
            edge,
            new Geom2d_Line(gp_Pnt2d(p0.x(), p0.y()),
                            gp_Dir2d(p1.x() - p0.x(), p1.y() - p0.y())),
            face, tolerance);
        builder.Add(wire,
                    edge.Oriented(forward ? TopAbs_FORWARD : TopAbs_REVERSED));
      }
      wire.Closed(true);
      builder.Add(face, wire);
      builder.Add(shell, face);
      ++report.faces;
    }
    for (const auto& [key, edge] : edges) {
      if (edge.second != 2) ++report.free_edges;
    }
    if (report.free_edges != 0) {
      return InternalError(path + ": the patches do not form a closed shell (" +
                           std::to_string(report.free_edges) +
                           " edges not shared by exactly two patches)");
    }
    shell.Closed(true);
    TopoDS_Solid solid;
    builder.MakeSolid(solid);
    builder.Add(solid, shell);
    report.seconds.build = t0.Seconds();
    t0.Restart();
    stage("checking", 0.2);
    report.valid =
        BRepCheck_Analyzer(solid, /*GeomControls=*/true, /*theIsParallel=*/true)
            .IsValid();
    report.seconds.check = t0.Seconds();
    if (!report.valid || !(report.volume > 0.0)) {
      return InternalError(path +
                           ": the solid is not valid (BRepCheck_Analyzer) or "
                           "encloses no volume");
    }
    t0.Restart();
    stage("translating", 0.5);
    const Status translated = format == CadFormat::kStep
                                  ? WriteStep(solid, path, &contents)
                                  : WriteIges(solid, path, &contents);
    if (!translated.ok()) return translated;
    report.seconds.translate = t0.Seconds();
  } catch (const Standard_Failure& failure) {
    return InternalError(path +
                         ": OpenCASCADE failed: " + failure.GetMessageString());
  }
  t0.Restart();
  stage("writing", 0.95);
  SDCB_RETURN_IF_ERROR(WriteFileAtomically(contents, path));
  report.seconds.write = t0.Seconds();
  report.bytes = static_cast<int64_t>(contents.size());
  return report;
}

void SilenceOpenCascadeMessages() {
  Message::DefaultMessenger()->RemovePrinters(
      STANDARD_TYPE(Message_PrinterOStream));
}

}  // namespace sdcb
