#include "sdcb/converters/cage/cage_fbx.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <utility>
#include <vector>

#include "sdcb/io/common/atomic_file.h"

namespace sdcb {
namespace {

// Binary FBX 7.4 (the layout Blender's io_scene_fbx/parse_fbx.py reads):
// a 27-byte header (magic, version), then node records, each
//   uint32 end offset (absolute), uint32 property count,
//   uint32 property bytes, uint8 name length, name, properties,
//   child records, and, when it has children or no properties, a 13-byte
//   null record closing the children;
// the top level closed by a null record too, then the footer. Little endian.
constexpr uint32_t kFbxVersion = 7400;
constexpr int kNullRecordBytes = 13;  // three uint32 and a name length

// The header, the footer's trailing magic, and a FileId / CreationTime /
// footer code triple: the FBX SDK is said to check that the three agree;
// this is the triple Blender's FBX exporter writes for every file (sdcb
// has no FBX SDK to check it with; Blender does not check it).
constexpr char kHeaderMagic[] = "Kaydara FBX Binary  \x00\x1a\x00";
constexpr int kHeaderMagicBytes = 23;
constexpr unsigned char kFileId[16] = {0x28, 0xb3, 0x2a, 0xeb, 0xb6, 0x24,
                                       0xcc, 0xc2, 0xbf, 0xc8, 0xb0, 0x2a,
                                       0xa9, 0x2b, 0xfc, 0xf1};
constexpr char kCreationTime[] = "1970-01-01 10:00:00:000";
constexpr unsigned char kFooterCode[16] = {0xfa, 0xbc, 0xab, 0x09, 0xd0, 0xc8,
                                           0xd4, 0x66, 0xb1, 0x76, 0xfb, 0x83,
                                           0x1c, 0xf7, 0x26, 0x7e};
constexpr unsigned char kFooterMagic[16] = {0xf8, 0x5a, 0x8c, 0x6a, 0xde, 0xf5,
                                            0xd9, 0x7e, 0xec, 0xe9, 0x0c, 0xe3,
                                            0x75, 0x8f, 0x29, 0x0b};

// Object ids (any distinct non-zero int64; 0 is the scene root).
constexpr int64_t kGeometryId = 1000001;
constexpr int64_t kModelId = 1000002;

// Writes node records into a byte string, patching each record's offsets
// when it is closed.
class FbxNodeWriter {
 public:
  FbxNodeWriter() {
    bytes_.append(kHeaderMagic, kHeaderMagicBytes);
    PutU32(kFbxVersion);
  }

  void Begin(const std::string& name) {
    if (!open_.empty()) {
      EndProperties(open_.back());
      open_.back().has_children = true;
    }
    Node node;
    node.start = bytes_.size();
    bytes_.append(12, '\0');  // patched by End()
    bytes_.push_back(static_cast<char>(name.size()));
    bytes_ += name;
    node.properties_start = bytes_.size();
    open_.push_back(node);
  }

  void End() {
    Node& node = open_.back();
    EndProperties(node);
    if (node.has_children || node.properties == 0) {
      bytes_.append(kNullRecordBytes, '\0');
    }
    PatchU32(node.start, static_cast<uint32_t>(bytes_.size()));
    PatchU32(node.start + 4, node.properties);
    PatchU32(node.start + 8, static_cast<uint32_t>(node.properties_end -
                                                   node.properties_start));
    open_.pop_back();
  }

  // Properties of the node begun last (before any of its children).
  void Int32(int32_t v) {
    Type('I');
    PutU32(static_cast<uint32_t>(v));
  }
  void Int64(int64_t v) {
    Type('L');
    PutU64(static_cast<uint64_t>(v));
  }
  void Double(double v) {
    Type('D');
    PutDouble(v);
  }
  void Bool(bool v) {
    Type('C');
    bytes_.push_back(v ? 1 : 0);
  }
  void String(const std::string& s) {
    Type('S');
    PutU32(static_cast<uint32_t>(s.size()));
    bytes_ += s;
  }
  void Raw(const unsigned char* data, size_t size) {
    Type('R');
    PutU32(static_cast<uint32_t>(size));
    bytes_.append(reinterpret_cast<const char*>(data), size);
  }
  // Arrays: count, encoding 0 (not compressed), byte length, elements.
  void Int32Array(const std::vector<int32_t>& values) {
    Type('i');
    ArrayHeader(values.size(), 4);
    for (int32_t v : values) PutU32(static_cast<uint32_t>(v));
  }
  void DoubleArray(const std::vector<double>& values) {
    Type('d');
    ArrayHeader(values.size(), 8);
    for (double v : values) PutDouble(v);
  }

  // A child node with one property.
  void Leaf(const std::string& name, int32_t v) {
    Begin(name);
    Int32(v);
    End();
  }
  void Leaf(const std::string& name, const std::string& v) {
    Begin(name);
    String(v);
    End();
  }

  // The top level's null record, then the footer.
  std::string Finish() && {
    bytes_.append(kNullRecordBytes, '\0');
    bytes_.append(reinterpret_cast<const char*>(kFooterCode), 16);
    bytes_.append(4, '\0');
    // Zeros up to a multiple of 16 bytes: at least one, at most 16.
    const size_t pad = 16 - bytes_.size() % 16;
    bytes_.append(pad, '\0');
    PutU32(kFbxVersion);
    bytes_.append(120, '\0');
    bytes_.append(reinterpret_cast<const char*>(kFooterMagic), 16);
    return std::move(bytes_);
  }

 private:
  struct Node {
    size_t start = 0, properties_start = 0, properties_end = 0;
    uint32_t properties = 0;
    bool has_children = false, properties_ended = false;
  };

  void EndProperties(Node& node) {
    if (node.properties_ended) return;
    node.properties_end = bytes_.size();
    node.properties_ended = true;
  }
  void Type(char type) {
    ++open_.back().properties;
    bytes_.push_back(type);
  }
  void ArrayHeader(size_t count, size_t element_bytes) {
    PutU32(static_cast<uint32_t>(count));
    PutU32(0);
    PutU32(static_cast<uint32_t>(count * element_bytes));
  }
  void PutU32(uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<char>(v >> 8 * i));
  }
  void PutU64(uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<char>(v >> 8 * i));
  }
  void PutDouble(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    PutU64(bits);
  }
  void PatchU32(size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_[at + i] = static_cast<char>(v >> 8 * i);
  }

  std::string bytes_;
  std::vector<Node> open_;
};

// A "P" entry of a Properties70 block: name, type, label, flags, value.
void IntProperty(FbxNodeWriter& w, const std::string& name, int32_t v) {
  w.Begin("P");
  w.String(name);
  w.String("int");
  w.String("Integer");
  w.String("");
  w.Int32(v);
  w.End();
}
void DoubleProperty(FbxNodeWriter& w, const std::string& name, double v) {
  w.Begin("P");
  w.String(name);
  w.String("double");
  w.String("Number");
  w.String("");
  w.Double(v);
  w.End();
}

// An undirected edge.
std::pair<int, int> EdgeKey(int a, int b) {
  return a < b ? std::make_pair(a, b) : std::make_pair(b, a);
}

// "name\0\1Class", FBX's object name with its class.
std::string ObjectName(const std::string& name, const std::string& cls) {
  return name + std::string("\x00\x01", 2) + cls;
}

}  // namespace

StatusOr<std::string> CageFbxBytes(const SubdivisionCage& cage,
                                   const Eigen::MatrixX3d& positions) {
  const SphereCage& layout = cage.layout;
  if (cage.scheme != SubdivisionScheme::kCatmullClark ||
      layout.face_size != 4) {
    return InvalidArgumentError(
        "FBX holds Catmull-Clark cages only (it has no Loop scheme); write a "
        "Loop cage as OBJ");
  }
  const int n = static_cast<int>(positions.rows());
  if (n != layout.num_vertices()) {
    return InvalidArgumentError(
        "the cage has " + std::to_string(layout.num_vertices()) +
        " vertices but " + std::to_string(n) + " positions were given");
  }

  // Faces: the last corner of each face as -(index + 1). Edges: each
  // undirected edge once, as the polygon-vertex index of the corner it
  // starts from at its first occurrence.
  std::vector<int32_t> polygon_vertices;
  std::vector<int32_t> edges;
  std::map<std::pair<int, int>, int> edge_index;
  for (const auto& f : OutwardCageFaces(cage, positions)) {
    for (int k = 0; k < 4; ++k) {
      const int a = f[k], b = f[(k + 1) % 4];
      if (a < 0 || a >= n) {
        return InvalidArgumentError("a cage face has the corner " +
                                    std::to_string(a) + ", out of range");
      }
      if (edge_index.emplace(EdgeKey(a, b), static_cast<int>(edges.size()))
              .second) {
        edges.push_back(static_cast<int32_t>(polygon_vertices.size()));
      }
      polygon_vertices.push_back(k == 3 ? -(a + 1) : a);
    }
  }
  std::vector<double> crease(edges.size(), 0.0);
  for (const auto& [a, b] : cage.creases) {
    const auto it = edge_index.find(EdgeKey(a, b));
    if (it == edge_index.end()) {
      return InvalidArgumentError("the crease " + std::to_string(a) + "-" +
                                  std::to_string(b) +
                                  " is not an edge of the cage");
    }
    crease[it->second] = 1.0;  // infinitely sharp in Blender (see header)
  }
  std::vector<double> coordinates(3 * static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) coordinates[3 * i + c] = positions(i, c);
  }

  FbxNodeWriter w;
  w.Begin("FBXHeaderExtension");
  w.Leaf("FBXHeaderVersion", 1003);
  w.Leaf("FBXVersion", static_cast<int32_t>(kFbxVersion));
  w.Leaf("EncryptionType", 0);
  w.Begin("CreationTimeStamp");  // fixed: the same cage gives the same bytes
  w.Leaf("Version", 1000);
  w.Leaf("Year", 1970);
  w.Leaf("Month", 1);
  w.Leaf("Day", 1);
  w.Leaf("Hour", 10);
  w.Leaf("Minute", 0);
  w.Leaf("Second", 0);
  w.Leaf("Millisecond", 0);
  w.End();
  w.Leaf("Creator", "sdcb cage");
  w.End();
  w.Begin("FileId");
  w.Raw(kFileId, sizeof kFileId);
  w.End();
  w.Leaf("CreationTime", kCreationTime);
  w.Leaf("Creator", "sdcb cage");

  // Blender's axes and the metre, so that Blender applies no conversion.
  w.Begin("GlobalSettings");
  w.Leaf("Version", 1000);
  w.Begin("Properties70");
  IntProperty(w, "UpAxis", 2);
  IntProperty(w, "UpAxisSign", 1);
  IntProperty(w, "FrontAxis", 1);
  IntProperty(w, "FrontAxisSign", -1);
  IntProperty(w, "CoordAxis", 0);
  IntProperty(w, "CoordAxisSign", 1);
  DoubleProperty(w, "UnitScaleFactor", 100.0);
  DoubleProperty(w, "OriginalUnitScaleFactor", 100.0);
  w.End();
  w.End();

  w.Begin("Definitions");
  w.Leaf("Version", 100);
  w.Leaf("Count", 3);
  for (const char* type : {"GlobalSettings", "Model", "Geometry"}) {
    w.Begin("ObjectType");
    w.String(type);
    w.Leaf("Count", 1);
    w.End();
  }
  w.End();

  w.Begin("Objects");
  w.Begin("Geometry");
  w.Int64(kGeometryId);
  w.String(ObjectName("sdcb_cage", "Geometry"));
  w.String("Mesh");
  w.Begin("Properties70");
  w.End();
  w.Leaf("GeometryVersion", 124);
  w.Begin("Vertices");
  w.DoubleArray(coordinates);
  w.End();
  w.Begin("PolygonVertexIndex");
  w.Int32Array(polygon_vertices);
  w.End();
  w.Begin("Edges");
  w.Int32Array(edges);
  w.End();
  // Subdivision data: FBX's subdivision meshes are Catmull-Clark.
  w.Leaf("PreviewDivisionLevels", 2);
  w.Leaf("RenderDivisionLevels", 3);
  w.Leaf("BoundaryRule", 1);
  if (!cage.creases.empty()) {
    w.Begin("LayerElementEdgeCrease");
    w.Int32(0);
    w.Leaf("Version", 101);
    w.Leaf("Name", "");
    w.Leaf("MappingInformationType", "ByEdge");
    w.Leaf("ReferenceInformationType", "Direct");
    w.Begin("EdgeCrease");
    w.DoubleArray(crease);
    w.End();
    w.End();
    w.Begin("Layer");
    w.Int32(0);
    w.Leaf("Version", 100);
    w.Begin("LayerElement");
    w.Leaf("Type", "LayerElementEdgeCrease");
    w.Leaf("TypedIndex", 0);
    w.End();
    w.End();
  }
  w.End();  // Geometry
  w.Begin("Model");
  w.Int64(kModelId);
  w.String(ObjectName("sdcb_cage", "Model"));
  w.String("Mesh");
  w.Leaf("Version", 232);
  w.Begin("Properties70");
  w.End();
  w.Begin("Shading");
  w.Bool(true);
  w.End();
  w.Leaf("Culling", "CullingOff");
  w.End();  // Model
  w.End();  // Objects

  // The model under the scene root, the geometry under the model.
  w.Begin("Connections");
  w.Begin("C");
  w.String("OO");
  w.Int64(kModelId);
  w.Int64(0);
  w.End();
  w.Begin("C");
  w.String("OO");
  w.Int64(kGeometryId);
  w.Int64(kModelId);
  w.End();
  w.End();
  return std::move(w).Finish();
}

Status WriteCageFbx(const SubdivisionCage& cage,
                    const Eigen::MatrixX3d& positions,
                    const std::string& path) {
  StatusOr<std::string> bytes = CageFbxBytes(cage, positions);
  if (!bytes.ok()) return bytes.status().WithPrefix(path);
  return WriteFileAtomically(*bytes, path);
}

}  // namespace sdcb
