// A Catmull-Clark cage as a binary FBX 7.4 file with its edge creases: the
// cage format Blender reads the creases from (docs/CAGE.md, "Creases in
// Blender"). Debian 12's Blender 3.4 is built without Alembic and USD, and
// its OBJ importer skips OpenSubdiv's crease tags; its FBX importer
// (io_scene_fbx) reads a mesh's LayerElementEdgeCrease.
//
// What the file holds: one Model ("sdcb_cage") and its Geometry (a Mesh):
// `Vertices` (doubles, the positions given), `PolygonVertexIndex` (the
// faces, counter-clockwise seen from outside, the last corner of each face
// stored as -(index + 1) as FBX marks it), `Edges` (every edge of the cage
// once, as the index into PolygonVertexIndex of the corner it starts at),
// and, when the cage has creases, a LayerElementEdgeCrease mapped ByEdge /
// Direct with 1.0 on every crease edge and 0.0 elsewhere. Blender's FBX
// importer stores the square root of an FBX crease (Blender squares creases
// on their way to OpenSubdiv), so 1.0 is its crease 1.0, fully sharp, as
// SubdivisionCage::creases are infinitely sharp (scripts/
// blender_crease_check.sh: the corners stay in place under its modifier). The
// geometry also carries PreviewDivisionLevels 2 / RenderDivisionLevels 3,
// which Blender turns into a Subdivision Surface modifier when imported with
// "Subdivision Data" on. GlobalSettings declare Blender's axes (Z up, -Y
// front, X right) and 1 unit = 1 m (UnitScaleFactor 100), so that Blender
// imports the coordinates unchanged. The bytes are the same for the same
// cage (fixed ids and creation time).
#ifndef SDCB_CONVERTERS_CAGE_CAGE_FBX_H_
#define SDCB_CONVERTERS_CAGE_CAGE_FBX_H_

#include <Eigen/Core>
#include <string>

#include "sdcb/converters/cage/subdivision_cage.h"
#include "sdcb/core/common/status.h"

namespace sdcb {

// The cage as binary FBX bytes. `positions`: #V by 3, the cage's vertices
// in the frame to write (e.g. the model's transform applied to
// cage.vertices); #V must equal cage.layout.num_vertices(). FBX has no Loop
// scheme (its subdivision meshes are Catmull-Clark), so a Loop cage is
// kInvalidArgument, as are a position count that does not match, a face
// corner out of range, and a crease that is not an edge of a face.
StatusOr<std::string> CageFbxBytes(const SubdivisionCage& cage,
                                   const Eigen::MatrixX3d& positions);

// Writes CageFbxBytes to `path` without leaving a partial file
// (io/common/atomic_file.h). Messages of file errors start with `path`.
Status WriteCageFbx(const SubdivisionCage& cage,
                    const Eigen::MatrixX3d& positions, const std::string& path);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAGE_CAGE_FBX_H_
