// Re-reads a STEP or IGES file with OpenCASCADE's own readers (the oracle of
// the CAD export tests) and measures what was read, independently of sdcb's
// writer: solids, validity (BRepCheck_Analyzer), free edges of the shells,
// volume and area (BRepGProp), points on the read surfaces and a fine
// triangulation of them for distances, and the jump of the normal across
// every edge shared by two faces.
#ifndef SDCB_TESTS_TESTING_OCCT_REREAD_H_
#define SDCB_TESTS_TESTING_OCCT_REREAD_H_

#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRep_Tool.hxx>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <GProp_GProps.hxx>
#include <Geom2d_Curve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <IGESControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <ShapeAnalysis_FreeBounds.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Vertex.hxx>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb::testing {

struct RereadShape {
  bool read = false;
  int solids = 0;
  int shells = 0;
  int faces = 0;
  int free_edges = 0;  // of the shells: 0 when every shell is closed
  bool valid = false;
  double volume = 0.0;
  double area = 0.0;
  // The largest tolerance of a read vertex or edge: what the reader had to
  // allow for the gaps it found between curves, surfaces and points.
  double max_tolerance = 0.0;
  TopoDS_Shape shape;
  std::vector<Handle(Geom_Surface)> surfaces;  // one per face
  std::vector<std::array<double, 4>> bounds;   // u0, u1, v0, v1 per face
};

inline RereadShape Reread(const std::string& path, bool iges) {
  RereadShape r;
  TopoDS_Shape shape;
  if (iges) {
    IGESControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) return r;
    reader.TransferRoots();
    shape = reader.OneShape();
  } else {
    STEPControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) return r;
    reader.TransferRoots();
    shape = reader.OneShape();
  }
  if (shape.IsNull()) return r;
  r.read = true;
  r.shape = shape;
  for (TopExp_Explorer it(shape, TopAbs_SOLID); it.More(); it.Next()) {
    ++r.solids;
  }
  for (TopExp_Explorer it(shape, TopAbs_SHELL); it.More(); it.Next()) {
    ++r.shells;
    ShapeAnalysis_FreeBounds bounds(it.Current());
    for (TopExp_Explorer e(bounds.GetOpenWires(), TopAbs_EDGE); e.More();
         e.Next()) {
      ++r.free_edges;
    }
  }
  r.valid = BRepCheck_Analyzer(shape).IsValid();
  for (TopExp_Explorer it(shape, TopAbs_EDGE); it.More(); it.Next()) {
    r.max_tolerance = std::max(
        r.max_tolerance, BRep_Tool::Tolerance(TopoDS::Edge(it.Current())));
  }
  for (TopExp_Explorer it(shape, TopAbs_VERTEX); it.More(); it.Next()) {
    r.max_tolerance = std::max(
        r.max_tolerance, BRep_Tool::Tolerance(TopoDS::Vertex(it.Current())));
  }
  GProp_GProps volume, area;
  // Adaptive to a relative error of 1e-10 (the default fixed rule is
  // inexact on faces of many knot spans).
  BRepGProp::VolumeProperties(shape, volume, 1e-10);
  BRepGProp::SurfaceProperties(shape, area, 1e-10);
  r.volume = volume.Mass();
  r.area = area.Mass();
  for (TopExp_Explorer it(shape, TopAbs_FACE); it.More(); it.Next()) {
    const TopoDS_Face face = TopoDS::Face(it.Current());
    r.surfaces.push_back(BRep_Tool::Surface(face));
    std::array<double, 4> b;
    r.surfaces.back()->Bounds(b[0], b[1], b[2], b[3]);
    r.bounds.push_back(b);
    ++r.faces;
  }
  return r;
}

// The read surfaces sampled on an (n + 1)^2 lattice of each face's
// parameter box, triangulated (two triangles per lattice cell), with each
// triangle's face. Vertices are exact points of the read surfaces.
struct SurfaceLattice {
  TriangleMesh mesh;
  std::vector<int> triangle_face;
  // The surfaces at the lattice cells' centres (for the chord error).
  Eigen::MatrixX3d cell_centres;
};

inline SurfaceLattice SampleSurfaces(const RereadShape& r, int n) {
  SurfaceLattice s;
  const int nf = r.faces;
  const int per_face = (n + 1) * (n + 1);
  s.mesh.vertices.resize(static_cast<Eigen::Index>(nf) * per_face, 3);
  s.mesh.faces.resize(static_cast<Eigen::Index>(nf) * n * n * 2, 3);
  s.cell_centres.resize(static_cast<Eigen::Index>(nf) * n * n, 3);
  for (int f = 0; f < nf; ++f) {
    const auto& b = r.bounds[f];
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        const gp_Pnt p = r.surfaces[f]->Value(b[0] + (b[1] - b[0]) * i / n,
                                              b[2] + (b[3] - b[2]) * j / n);
        s.mesh.vertices.row(f * per_face + j * (n + 1) + i) << p.X(), p.Y(),
            p.Z();
      }
    }
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const int v = f * per_face + j * (n + 1) + i;
        const Eigen::Index t =
            (static_cast<Eigen::Index>(f) * n * n + j * n + i);
        s.mesh.faces.row(2 * t) << v, v + 1, v + n + 2;
        s.mesh.faces.row(2 * t + 1) << v, v + n + 2, v + n + 1;
        s.triangle_face.push_back(f);
        s.triangle_face.push_back(f);
        const gp_Pnt c =
            r.surfaces[f]->Value(b[0] + (b[1] - b[0]) * (i + 0.5) / n,
                                 b[2] + (b[3] - b[2]) * (j + 0.5) / n);
        s.cell_centres.row(t) << c.X(), c.Y(), c.Z();
      }
    }
  }
  return s;
}

// The distance from x to the read surface of face `f` (OpenCASCADE's
// projection; infinity if it finds no point).
inline double DistanceToFace(const RereadShape& r, int f,
                             const Eigen::Vector3d& x) {
  const auto& b = r.bounds[f];
  GeomAPI_ProjectPointOnSurf projection(gp_Pnt(x.x(), x.y(), x.z()),
                                        r.surfaces[f], b[0], b[1], b[2], b[3]);
  if (projection.NbPoints() == 0) return HUGE_VAL;
  return projection.LowerDistance();
}

// The largest and smallest angle between the two faces' outward normals across
// the edges shared by two faces, at `per_edge` points of every edge (evenly in
// its parameter, ends included): each face's point from the edge's pcurve
// on it, its normal from the surface's derivatives there, flipped for a
// reversed face.
struct NormalJumps {
  double max_degrees = 0.0;
  double min_degrees = 180.0;  // the smallest angle measured
  int edges = 0;
  int64_t points = 0;
};

inline NormalJumps MeasureNormalJumps(const RereadShape& r, int per_edge) {
  NormalJumps j;
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  TopExp::MapShapesAndAncestors(r.shape, TopAbs_EDGE, TopAbs_FACE, edge_faces);
  for (int e = 1; e <= edge_faces.Extent(); ++e) {
    const TopoDS_Edge edge = TopoDS::Edge(edge_faces.FindKey(e));
    const TopTools_ListOfShape& faces = edge_faces.FindFromIndex(e);
    if (faces.Extent() != 2) continue;
    ++j.edges;
    std::array<TopoDS_Face, 2> face = {TopoDS::Face(faces.First()),
                                       TopoDS::Face(faces.Last())};
    double first = 0.0, last = 0.0;
    BRep_Tool::Range(edge, first, last);
    for (int k = 0; k < per_edge; ++k) {
      const double t = first + (last - first) * k / (per_edge - 1);
      Eigen::Vector3d normal[2];
      for (int s = 0; s < 2; ++s) {
        double f0 = 0.0, f1 = 0.0;
        const Handle(Geom2d_Curve) pcurve =
            BRep_Tool::CurveOnSurface(edge, face[s], f0, f1);
        const gp_Pnt2d uv = pcurve->Value(t);
        gp_Pnt p;
        gp_Vec du, dv;
        BRep_Tool::Surface(face[s])->D1(uv.X(), uv.Y(), p, du, dv);
        const gp_Vec n = du.Crossed(dv);
        normal[s] = Eigen::Vector3d(n.X(), n.Y(), n.Z());
        if (face[s].Orientation() == TopAbs_REVERSED) normal[s] = -normal[s];
      }
      const double angle = std::atan2(normal[0].cross(normal[1]).norm(),
                                      normal[0].dot(normal[1])) *
                           180.0 / kPi;
      j.max_degrees = std::max(j.max_degrees, angle);
      j.min_degrees = std::min(j.min_degrees, angle);
      ++j.points;
    }
  }
  return j;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_OCCT_REREAD_H_
