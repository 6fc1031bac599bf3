// A test-side reader of binary FBX files (node records with their
// properties), written from the format's description and sharing no code
// with converters/cage/cage_fbx: what the cage tests read the written .fbx back
// with. Reads versions 7100 to 7700 (32-bit record offsets below 7500,
// 64-bit from 7500); arrays must be stored uncompressed (encoding 0), which
// is all sdcb writes.
#ifndef SDCB_TESTS_TESTING_FBX_BINARY_READER_H_
#define SDCB_TESTS_TESTING_FBX_BINARY_READER_H_

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace sdcb::testing {

struct FbxProperty {
  char type = 0;  // Y C I L F D S R, or f d i l b c for arrays
  int64_t integer = 0;
  double number = 0.0;
  std::string bytes;              // S, R
  std::vector<double> numbers;    // f, d
  std::vector<int64_t> integers;  // i, l, b, c
};

struct FbxNode {
  std::string name;
  std::vector<FbxProperty> properties;
  std::vector<FbxNode> children;

  // The first child named `child`, or nullptr.
  const FbxNode* Find(const std::string& child) const {
    for (const FbxNode& c : children) {
      if (c.name == child) return &c;
    }
    return nullptr;
  }
};

struct FbxDocument {
  uint32_t version = 0;
  FbxNode root;  // unnamed; the top-level nodes are its children
};

namespace fbx_detail {

class Cursor {
 public:
  explicit Cursor(const std::string& data) : data_(data) {}
  size_t position() const { return position_; }
  const char* Take(size_t n) {
    if (n > data_.size() - position_) throw std::runtime_error("truncated");
    const char* p = data_.data() + position_;
    position_ += n;
    return p;
  }
  template <typename T>
  T Read() {
    T v;
    std::memcpy(&v, Take(sizeof v), sizeof v);  // the file is little endian
    return v;
  }

 private:
  const std::string& data_;
  size_t position_ = 0;
};

template <typename T>
void ReadArray(Cursor& in, FbxProperty& p) {
  const uint32_t count = in.Read<uint32_t>();
  const uint32_t encoding = in.Read<uint32_t>();
  const uint32_t length = in.Read<uint32_t>();
  if (encoding != 0) throw std::runtime_error("compressed array");
  if (length != count * sizeof(T)) throw std::runtime_error("array length");
  for (uint32_t i = 0; i < count; ++i) {
    const T v = in.Read<T>();
    if constexpr (std::is_floating_point_v<T>) {
      p.numbers.push_back(v);
    } else {
      p.integers.push_back(v);
    }
  }
}

inline FbxProperty ReadProperty(Cursor& in) {
  FbxProperty p;
  p.type = in.Read<char>();
  switch (p.type) {
    case 'Y':
      p.integer = in.Read<int16_t>();
      break;
    case 'C':
      p.integer = in.Read<uint8_t>();
      break;
    case 'I':
      p.integer = in.Read<int32_t>();
      break;
    case 'L':
      p.integer = in.Read<int64_t>();
      break;
    case 'F':
      p.number = in.Read<float>();
      break;
    case 'D':
      p.number = in.Read<double>();
      break;
    case 'S':
    case 'R': {
      const uint32_t n = in.Read<uint32_t>();
      p.bytes.assign(in.Take(n), n);
      break;
    }
    case 'f':
      ReadArray<float>(in, p);
      break;
    case 'd':
      ReadArray<double>(in, p);
      break;
    case 'i':
      ReadArray<int32_t>(in, p);
      break;
    case 'l':
      ReadArray<int64_t>(in, p);
      break;
    case 'b':
    case 'c':
      ReadArray<uint8_t>(in, p);
      break;
    default:
      throw std::runtime_error(std::string("property type ") + p.type);
  }
  return p;
}

// One record; false for a null record (the end of a list of nodes).
inline bool ReadNode(Cursor& in, bool wide, FbxNode& node) {
  const auto word = [&]() -> uint64_t {
    return wide ? in.Read<uint64_t>() : in.Read<uint32_t>();
  };
  const uint64_t end = word();
  const uint64_t properties = word();
  const uint64_t property_bytes = word();
  const uint8_t name_length = in.Read<uint8_t>();
  if (end == 0 && properties == 0 && property_bytes == 0 && name_length == 0) {
    return false;
  }
  node.name.assign(in.Take(name_length), name_length);
  const size_t properties_start = in.position();
  for (uint64_t i = 0; i < properties; ++i) {
    node.properties.push_back(ReadProperty(in));
  }
  if (in.position() - properties_start != property_bytes) {
    throw std::runtime_error(node.name + ": property byte count");
  }
  if (in.position() < end) {
    // Children, closed by a null record.
    for (;;) {
      FbxNode child;
      if (!ReadNode(in, wide, child)) break;
      node.children.push_back(std::move(child));
    }
  }
  if (in.position() != end) {
    throw std::runtime_error(node.name + ": end offset");
  }
  return true;
}

}  // namespace fbx_detail

// Parses `data` (a whole file); throws std::runtime_error naming what is
// wrong.
inline FbxDocument ParseFbxBinary(const std::string& data) {
  static const char kMagic[] = "Kaydara FBX Binary  \x00\x1a\x00";
  if (data.size() < 27 || std::memcmp(data.data(), kMagic, 23) != 0) {
    throw std::runtime_error("not a binary FBX file");
  }
  fbx_detail::Cursor in(data);
  in.Take(23);
  FbxDocument doc;
  doc.version = in.Read<uint32_t>();
  if (doc.version < 7100 || doc.version > 7700) {
    throw std::runtime_error("version " + std::to_string(doc.version));
  }
  for (;;) {
    FbxNode node;
    if (!fbx_detail::ReadNode(in, doc.version >= 7500, node)) break;
    doc.root.children.push_back(std::move(node));
  }
  return doc;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_FBX_BINARY_READER_H_
