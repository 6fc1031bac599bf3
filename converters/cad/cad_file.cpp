#include "sdcb/converters/cad/cad_file.h"

#include <APIHeaderSection_MakeHeader.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRep_Builder.hxx>
#include <Geom2d_Line.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_EntityIterator.hxx>
#include <Interface_FloatWriter.hxx>
#include <Interface_Graph.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Precision.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <StepData_Protocol.hxx>
#include <StepData_StepModel.hxx>
#include <StepData_StepWriter.hxx>
#include <StepGeom_BSplineCurve.hxx>
#include <StepGeom_BSplineSurface.hxx>
#include <StepGeom_CartesianPoint.hxx>
#include <StepGeom_Direction.hxx>
#include <StepGeom_HArray1OfCartesianPoint.hxx>
#include <StepGeom_HArray2OfCartesianPoint.hxx>
#include <StepGeom_Line.hxx>
#include <StepGeom_Vector.hxx>
#include <StepShape_VertexPoint.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <XSControl_WorkSession.hxx>
#include <algorithm>
#include <map>
#include <sstream>

#include "sdcb/core/common/progress.h"
#include "sdcb/core/common/stopwatch.h"
#include "sdcb/io/common/atomic_file.h"

namespace sdcb {
namespace {

// A knot vector of `breaks` in OpenCASCADE's form: the distinct knots and
// their multiplicities (4 at the ends, 1 inside).
struct OcctKnots {
  TColStd_Array1OfReal knots;
  TColStd_Array1OfInteger multiplicities;
  explicit OcctKnots(const KnotBreaks& breaks)
      : knots(1, static_cast<int>(breaks.size())),
        multiplicities(1, static_cast<int>(breaks.size())) {
    for (size_t k = 0; k < breaks.size(); ++k) {
      knots.SetValue(static_cast<int>(k) + 1, breaks[k]);
      multiplicities.SetValue(static_cast<int>(k) + 1,
                              k == 0 || k + 1 == breaks.size() ? 4 : 1);
    }
  }
};

gp_Pnt ToPoint(const Eigen::Vector3d& p) { return gp_Pnt(p.x(), p.y(), p.z()); }

Handle(Geom_BSplineSurface) MakeSurface(const BSplineFace& face) {
  const int nu = face.num_u(), nv = face.num_v();
  TColgp_Array2OfPnt poles(1, nu, 1, nv);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      poles.SetValue(i + 1, j + 1, ToPoint(face.poles[j * nu + i]));
    }
  }
  const OcctKnots u(face.u_breaks), v(face.v_breaks);
  return new Geom_BSplineSurface(poles, u.knots, v.knots, u.multiplicities,
                                 v.multiplicities, 3, 3);
}

Handle(Geom_BSplineCurve) MakeCurve(const CadEdge& edge) {
  TColgp_Array1OfPnt poles(1, static_cast<int>(edge.poles.size()));
  for (size_t q = 0; q < edge.poles.size(); ++q) {
    poles.SetValue(static_cast<int>(q) + 1, ToPoint(edge.poles[q]));
  }
  const OcctKnots knots(edge.breaks);
  return new Geom_BSplineCurve(poles, knots.knots, knots.multiplicities, 3);
}

// The pcurve of side k of `face` (CadNetwork's numbering): the line of the
// face's parameter box that the side's parameter t runs along.
Handle(Geom2d_Line) SideLine(const BSplineFace& face, int k) {
  switch (k) {
    case 0:
      return new Geom2d_Line(gp_Pnt2d(0.0, face.v_breaks.front()),
                             gp_Dir2d(1.0, 0.0));
    case 1:
      return new Geom2d_Line(gp_Pnt2d(face.u_breaks.back(), 0.0),
                             gp_Dir2d(0.0, 1.0));
    case 2:
      return new Geom2d_Line(gp_Pnt2d(0.0, face.v_breaks.back()),
                             gp_Dir2d(1.0, 0.0));
    default:
      return new Geom2d_Line(gp_Pnt2d(face.u_breaks.front(), 0.0),
                             gp_Dir2d(0.0, 1.0));
  }
}

// The resolution of the reals of a STEP file: every coordinate, knot and
// parameter below 10^5 in magnitude is written with 8 decimals, 5e-9 mm at
// most between a value and its text, below OpenCASCADE's confusion distance
// (1e-7 mm); its own default of 12 decimals spends a third of the file on
// digits no reader can use. Larger values keep its exponent form with 12
// decimals (OpenCASCADE's zero suppression reads only the first 16
// characters of a value, which bounds both forms).
void SetStepRealFormat(Interface_FloatWriter* writer) {
  writer->SetFormat("%.12E");
  writer->SetFormatForRange("%.8f", 0.0, 1.0e5);
  writer->SetZeroSuppress(true);
}

// A CARTESIAN_POINT or DIRECTION's values as the file will spell them.
std::string RealsText(const Interface_FloatWriter& writer, int count,
                      const std::function<double(int)>& value) {
  std::string text;
  char spelled[64];
  for (int i = 1; i <= count; ++i) {
    writer.Write(value(i), spelled);
    text += spelled;
    text += ',';
  }
  return text;
}

std::string PointText(const Interface_FloatWriter& writer,
                      const StepGeom_CartesianPoint& point) {
  return RealsText(writer, point.NbCoordinates(),
                   [&](int i) { return point.CoordinatesValue(i); });
}

std::string DirectionText(const Interface_FloatWriter& writer,
                          const StepGeom_Direction& direction) {
  return RealsText(writer, direction.NbDirectionRatios(),
                   [&](int i) { return direction.DirectionRatiosValue(i); });
}

// The translated model with every point and direction written once: poles
// that a face's boundary row shares with its edge's curve (or a corner with
// its faces, edges and vertex) and the pcurves' directions are the same text
// many times over, and STEP lets every surface, curve, vertex and vector
// refer to one CARTESIAN_POINT or DIRECTION entity. The references are
// pointed at the first entity of each text (model order), and the points and
// directions no entity refers to any more are dropped.
void ShareEqualPoints(const Handle(StepData_StepModel) & model,
                      const Handle(StepData_Protocol) & protocol,
                      const Interface_FloatWriter& writer) {
  std::map<std::string, Handle(StepGeom_CartesianPoint)> points;
  std::map<std::string, Handle(StepGeom_Direction)> directions;
  const auto point = [&](const Handle(StepGeom_CartesianPoint) & p) {
    if (p.IsNull()) return p;
    return points.emplace(PointText(writer, *p), p).first->second;
  };
  const int count = model->NbEntities();
  for (int n = 1; n <= count; ++n) {
    const Handle(Standard_Transient)& entity = model->Value(n);
    if (const auto p = Handle(StepGeom_CartesianPoint)::DownCast(entity)) {
      point(p);
    } else if (const auto d = Handle(StepGeom_Direction)::DownCast(entity)) {
      directions.emplace(DirectionText(writer, *d), d);
    }
  }
  for (int n = 1; n <= count; ++n) {
    const Handle(Standard_Transient)& entity = model->Value(n);
    if (const auto s = Handle(StepGeom_BSplineSurface)::DownCast(entity)) {
      const Handle(StepGeom_HArray2OfCartesianPoint) poles =
          s->ControlPointsList();
      if (poles.IsNull()) continue;
      for (int i = poles->LowerRow(); i <= poles->UpperRow(); ++i) {
        for (int j = poles->LowerCol(); j <= poles->UpperCol(); ++j) {
          poles->SetValue(i, j, point(poles->Value(i, j)));
        }
      }
    } else if (const auto c = Handle(StepGeom_BSplineCurve)::DownCast(entity)) {
      const Handle(StepGeom_HArray1OfCartesianPoint) poles =
          c->ControlPointsList();
      if (poles.IsNull()) continue;
      for (int i = poles->Lower(); i <= poles->Upper(); ++i) {
        poles->SetValue(i, point(poles->Value(i)));
      }
    } else if (const auto v = Handle(StepShape_VertexPoint)::DownCast(entity)) {
      const auto p =
          Handle(StepGeom_CartesianPoint)::DownCast(v->VertexGeometry());
      if (!p.IsNull()) v->SetVertexGeometry(point(p));
    } else if (const auto l = Handle(StepGeom_Line)::DownCast(entity)) {
      l->SetPnt(point(l->Pnt()));
    } else if (const auto e = Handle(StepGeom_Vector)::DownCast(entity)) {
      const Handle(StepGeom_Direction) d = e->Orientation();
      if (d.IsNull()) continue;
      e->SetOrientation(
          directions.emplace(DirectionText(writer, *d), d).first->second);
    }
  }
  const Interface_Graph graph(model, protocol);
  std::vector<Handle(Standard_Transient)> kept;
  kept.reserve(count);
  for (int n = 1; n <= count; ++n) {
    const Handle(Standard_Transient)& entity = model->Value(n);
    const bool leaf = entity->IsKind(STANDARD_TYPE(StepGeom_CartesianPoint)) ||
                      entity->IsKind(STANDARD_TYPE(StepGeom_Direction));
    if (!leaf || graph.Sharings(entity).NbEntities() > 0)
      kept.push_back(entity);
  }
  model->ClearEntities();
  for (const Handle(Standard_Transient) & entity : kept) {
    model->AddEntity(entity);
  }
}

// Writes `shape` with OpenCASCADE's STEP translator and Part 21 writer into
// `contents`, equal points shared and reals at SetStepRealFormat's
// resolution.
Status WriteStep(const TopoDS_Shape& solid, const std::string& path,
                 std::string* contents) {
  STEPControl_Writer writer;
  if (writer.Transfer(solid, STEPControl_ManifoldSolidBrep) !=
      IFSelect_RetDone) {
    return InternalError(path +
                         ": OpenCASCADE could not translate the solid "
                         "to STEP");
  }
  const Handle(StepData_StepModel) model = writer.Model();
  const Handle(StepData_Protocol) protocol =
      Handle(StepData_Protocol)::DownCast(writer.WS()->Protocol());
  if (model.IsNull() || protocol.IsNull()) {
    return InternalError(path + ": OpenCASCADE made no STEP model");
  }
  // The header's time stamp is fixed (the Unix epoch), so that the same
  // model gives the same bytes.
  APIHeaderSection_MakeHeader header(model);
  header.SetTimeStamp(new TCollection_HAsciiString("1970-01-01T00:00:00"));
  Interface_FloatWriter reals;
  SetStepRealFormat(&reals);
  ShareEqualPoints(model, protocol, reals);
  StepData_StepWriter step(model);
  step.FloatWriter() = reals;
  step.SendModel(protocol);
  std::ostringstream buffer;
  if (!step.Print(buffer) || buffer.str().empty()) {
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
  // The global section's dates are fixed (the Unix epoch), so that the same
  // model gives the same bytes.
  IGESData_GlobalSection global = writer.Model()->GlobalSection();
  global.SetDate(IGESData_GlobalSection::NewDateString(1970, 1, 1, 0, 0, 0));
  global.SetLastChangeDate(
      IGESData_GlobalSection::NewDateString(1970, 1, 1, 0, 0, 0));
  writer.Model()->SetGlobalSection(global);
  std::ostringstream buffer;
  if (!writer.Write(buffer) || buffer.str().empty()) {
    return IoError(path + ": OpenCASCADE could not write the IGES file");
  }
  *contents = buffer.str();
  return Status::Ok();
}

}  // namespace

namespace {

// The solid of `network` (see WriteCadSolid), with the report's faces,
// free edges, tolerance, volume, area, validity and build / check seconds.
// `path` names the file in messages. OpenCASCADE's exceptions pass through.
StatusOr<TopoDS_Solid> BuildSolid(const CadNetwork& network,
                                  const std::string& path,
                                  CadSolidReport* report) {
  const std::vector<BSplineFace>& faces = network.faces;
  if (faces.empty() || faces.size() != network.face_edges.size()) {
    return InvalidArgumentError(path +
                                ": no faces, or not four edges per face");
  }
  Stopwatch t0;
  // The faces are counter-clockwise seen from their sphere parameters' side,
  // which is outside unless the model was fitted to a mesh whose faces point
  // inward (its parameterization then mirrors the sphere): the faces' signed
  // volume says which, and inward faces enter the shell reversed, so that
  // the solid is oriented outward either way.
  std::vector<BicubicPatch> patches;
  for (const BSplineFace& face : faces) {
    const std::vector<BicubicPatch> spans = face.BezierPatches();
    patches.insert(patches.end(), spans.begin(), spans.end());
  }
  const PatchSetMeasures measures = MeasurePatchSet(patches);
  const bool inward = measures.volume < 0.0;
  report->volume = std::abs(measures.volume);
  report->area = measures.area;
  // Each face's boundary is its edges' curves (with the face's knots
  // inserted), so the shared edges are known: the shell is built
  // topologically (one vertex per corner, one edge per shared side whose
  // 3D curve is the edge's curve, with a straight pcurve in each of its two
  // faces), not sewn.
  report->tolerance = Precision::Confusion();
  const double tolerance = report->tolerance;
  BRep_Builder builder;
  std::vector<TopoDS_Vertex> vertices(network.num_vertices);
  std::vector<bool> made(network.num_vertices, false);
  const auto vertex = [&](int index, const Eigen::Vector3d& p) {
    if (!made[index]) {
      builder.MakeVertex(vertices[index], ToPoint(p), tolerance);
      made[index] = true;
    }
    return vertices[index];
  };
  std::vector<TopoDS_Edge> edges(network.edges.size());
  std::vector<int> uses(network.edges.size(), 0);
  TopoDS_Shell shell;
  builder.MakeShell(shell);
  for (size_t f = 0; f < faces.size(); ++f) {
    TopoDS_Face face;
    builder.MakeFace(face, MakeSurface(faces[f]), tolerance);
    TopoDS_Wire wire;
    builder.MakeWire(wire);
    for (int k = 0; k < 4; ++k) {
      const int e = network.face_edges[f][k];
      const CadEdge& curve = network.edges[e];
      TopoDS_Edge& edge = edges[e];
      if (uses[e]++ == 0) {
        builder.MakeEdge(edge, MakeCurve(curve), tolerance);
        builder.Add(
            edge,
            vertex(curve.start, curve.poles.front()).Oriented(TopAbs_FORWARD));
        builder.Add(
            edge,
            vertex(curve.end, curve.poles.back()).Oriented(TopAbs_REVERSED));
        builder.Range(edge, curve.breaks.front(), curve.breaks.back());
      }
      builder.UpdateEdge(edge, SideLine(faces[f], k), face, tolerance);
      builder.Add(wire,
                  edge.Oriented(k < 2 ? TopAbs_FORWARD : TopAbs_REVERSED));
    }
    wire.Closed(true);
    builder.Add(face, wire);
    builder.Add(shell, inward ? TopoDS::Face(face.Reversed()) : face);
    ++report->faces;
  }
  for (const int n : uses) {
    if (n != 2) ++report->free_edges;
  }
  if (report->free_edges != 0) {
    return InternalError(path + ": the faces do not form a closed shell (" +
                         std::to_string(report->free_edges) +
                         " edges not shared by exactly two faces)");
  }
  shell.Closed(true);
  TopoDS_Solid solid;
  builder.MakeSolid(solid);
  builder.Add(solid, shell);
  report->seconds.build = t0.Seconds();
  t0.Restart();
  report->valid =
      BRepCheck_Analyzer(solid, /*GeomControls=*/true, /*theIsParallel=*/true)
          .IsValid();
  report->seconds.check = t0.Seconds();
  if (!report->valid || !(report->volume > 0.0)) {
    return InternalError(path +
                         ": the solid is not valid (BRepCheck_Analyzer) or "
                         "encloses no volume");
  }
  return solid;
}

}  // namespace

StatusOr<CadSolidReport> WriteCadSolid(const CadNetwork& network,
                                       CadFormat format,
                                       const std::string& path,
                                       const ProgressCallback& progress) {
  return WriteCadSolids({network}, format, path, progress);
}

StatusOr<CadSolidReport> WriteCadSolids(const std::vector<CadNetwork>& networks,
                                        CadFormat format,
                                        const std::string& path,
                                        const ProgressCallback& progress) {
  const auto stage = [&](const char* name, double fraction) {
    if (progress) progress(name, fraction);
  };
  if (networks.empty()) return InvalidArgumentError(path + ": no solids");
  CadSolidReport report;
  report.valid = true;
  std::string contents;
  try {
    std::vector<TopoDS_Solid> solids;
    for (size_t i = 0; i < networks.size(); ++i) {
      // The first solid's stage starts as it always did.
      if (i > 0) stage("checking", 0.2 * i / networks.size());
      CadSolidReport one;
      StatusOr<TopoDS_Solid> solid = BuildSolid(networks[i], path, &one);
      if (!solid.ok()) return solid.status();
      if (i == 0) stage("checking", 0.2);
      solids.push_back(*solid);
      report.faces += one.faces;
      report.free_edges += one.free_edges;
      report.tolerance = std::max(report.tolerance, one.tolerance);
      report.valid = report.valid && one.valid;
      report.volume += one.volume;
      report.area += one.area;
      report.seconds.build += one.seconds.build;
      report.seconds.check += one.seconds.check;
    }
    Stopwatch t0;
    stage("translating", 0.5);
    // One solid is written as itself (as always); several as a compound.
    TopoDS_Shape shape = solids[0];
    if (solids.size() > 1) {
      BRep_Builder builder;
      TopoDS_Compound compound;
      builder.MakeCompound(compound);
      for (const TopoDS_Solid& solid : solids) builder.Add(compound, solid);
      shape = compound;
    }
    const Status translated = format == CadFormat::kStep
                                  ? WriteStep(shape, path, &contents)
                                  : WriteIges(shape, path, &contents);
    if (!translated.ok()) return translated;
    report.seconds.translate = t0.Seconds();
  } catch (const Standard_Failure& failure) {
    return InternalError(path +
                         ": OpenCASCADE failed: " + failure.GetMessageString());
  }
  Stopwatch t0;
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
