// The PLY reader (surface_mesh_internal.h): ascii, binary_little_endian and binary_big_endian 1.0. The
// vertex element's x, y, z (any numeric type) and the face element's list "vertex_indices" (or
// "vertex_index"; any integer count and index types) are read, and texture coordinates: per face corner
// from the face's list "texcoord" (MeshLab's: u v per corner, in the index list's order), else per vertex
// from its "s" "t", "texture_u" "texture_v" or "u" "v"; every other property (normals, colours, kinds) and
// element (edges, materials) is read past and ignored. Polygons become fans from their first
// vertex. Errors name file:line in the header and in ascii data, the byte offset in binary data.
// Bounded: a binary element count is checked against the bytes left before anything is read.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "surface_mesh_internal.h"

namespace incise::mesh::detail {

namespace {

enum class Encoding { Ascii, Little, Big };

struct Type {
  int bytes = 0;  // 0: not a type
  bool integer = true, is_signed = true;
};

Type typeNamed(std::string_view name) {
  static const std::array<std::pair<std::string_view, Type>, 16> kTypes = {{
      {"char", {1, true, true}},
      {"int8", {1, true, true}},
      {"uchar", {1, true, false}},
      {"uint8", {1, true, false}},
      {"short", {2, true, true}},
      {"int16", {2, true, true}},
      {"ushort", {2, true, false}},
      {"uint16", {2, true, false}},
      {"int", {4, true, true}},
      {"int32", {4, true, true}},
      {"uint", {4, true, false}},
      {"uint32", {4, true, false}},
      {"float", {4, false, true}},
      {"float32", {4, false, true}},
      {"double", {8, false, true}},
      {"float64", {8, false, true}},
  }};
  for (const auto& [n, t] : kTypes)
    if (n == name) return t;
  return {};
}

struct Property {
  std::string name;
  Type type;
  Type count_type;  // bytes == 0: not a list
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;
};

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
  size_t data_offset = 0;      // the byte after "end_header\n"
  std::int64_t data_line = 0;  // the line "end_header" is on
};

Type parseType(const RawMesh& raw, std::int64_t line, std::string_view name) {
  const Type t = typeNamed(name);
  if (t.bytes == 0) fail(raw.at(line) + "unknown PLY property type '" + std::string(name) + "'");
  return t;
}

void parseProperty(const RawMesh& raw, std::int64_t line, const std::vector<std::string_view>& tokens, Header& header) {
  if (header.elements.empty()) fail(raw.at(line) + "a property before any element");
  Property p;
  if (tokens.size() == 5 && tokens[1] == "list") {
    p.count_type = parseType(raw, line, tokens[2]);
    p.type = parseType(raw, line, tokens[3]);
    if (!p.count_type.integer) fail(raw.at(line) + "a list count must have an integer type");
  } else if (tokens.size() == 3) {
    p.type = parseType(raw, line, tokens[1]);
  } else {
    fail(raw.at(line) + "expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
  }
  p.name = std::string(tokens.back());
  header.elements.back().properties.push_back(p);
}

void parseHeaderLine(const RawMesh& raw, std::int64_t line, const std::vector<std::string_view>& tokens,
                     Header& header) {
  const std::string_view keyword = tokens[0];
  if (keyword == "comment" || keyword == "obj_info") return;
  if (keyword == "format") {
    if (tokens.size() != 3 || tokens[2] != "1.0") fail(raw.at(line) + "expected 'format ENCODING 1.0'");
    if (tokens[1] == "ascii")
      header.encoding = Encoding::Ascii;
    else if (tokens[1] == "binary_little_endian")
      header.encoding = Encoding::Little;
    else if (tokens[1] == "binary_big_endian")
      header.encoding = Encoding::Big;
    else
      fail(raw.at(line) + "unknown PLY format '" + std::string(tokens[1]) + "'");
  } else if (keyword == "element") {
    const auto count = tokens.size() == 3 ? parseInteger(tokens[2]) : std::nullopt;
    if (!count || *count < 0 || *count > std::numeric_limits<int>::max())
      fail(raw.at(line) + "expected 'element NAME COUNT' with a count from 0 to 2^31 - 1");
    header.elements.push_back({std::string(tokens[1]), *count, {}});
  } else if (keyword == "property") {
    parseProperty(raw, line, tokens, header);
  } else {
    fail(raw.at(line) + "unknown PLY header line '" + std::string(keyword) + "'");
  }
}

Header parseHeader(const RawMesh& raw, const std::string& bytes) {
  Header header;
  size_t pos = 0;
  std::vector<std::string_view> tokens;
  for (std::int64_t line = 1;; ++line) {
    const size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) fail(raw.file + ": the PLY header has no 'end_header' line");
    std::string_view text = std::string_view(bytes).substr(pos, end - pos);
    pos = end + 1;
    splitTokens(text, tokens);
    if (line == 1) {
      if (tokens.size() != 1 || tokens[0] != "ply") fail(raw.at(1) + "not a PLY file (the first line is not 'ply')");
      continue;
    }
    if (tokens.empty()) continue;
    if (tokens[0] == "end_header") {
      header.data_offset = pos;
      header.data_line = line;
      return header;
    }
    parseHeaderLine(raw, line, tokens, header);
  }
}

// The values of the data section in order, as doubles (exact for every PLY integer type).
class Values {
 public:
  Values(const RawMesh& raw, const std::string& bytes, const Header& header)
      : raw_(raw),
        bytes_(bytes),
        encoding_(header.encoding),
        pos_(header.data_offset),
        lines_(std::string_view(bytes).substr(header.data_offset)),
        line0_(header.data_line) {}

  double next(Type type, const std::string& what) {
    return encoding_ == Encoding::Ascii ? nextText(type, what) : nextBinary(type, what);
  }
  // Where the next value is: the line (ascii) or the byte offset (binary), for RawMesh::at.
  std::int64_t where() const {
    return encoding_ == Encoding::Ascii ? line0_ + lines_.line() : static_cast<std::int64_t>(pos_);
  }
  size_t bytesLeft() const { return bytes_.size() - std::min(pos_, bytes_.size()); }

 private:
  double nextText(Type type, const std::string& what) {
    while (k_ >= tokens_.size()) {
      if (!lines_.nextTokens(tokens_, false)) fail(raw_.file + ": the file ends inside " + what);
      k_ = 0;
    }
    const std::string at = raw_.at(where()) + what + ": ";
    const std::string_view token = tokens_[k_++];
    if (!type.integer) return parseCoordinate(token, at);
    const auto value = parseInteger(token);
    if (!value) fail(at + "'" + std::string(token) + "' is not an integer");
    return static_cast<double>(*value);
  }

  double nextBinary(Type type, const std::string& what) {
    const auto n = static_cast<size_t>(type.bytes);
    if (bytesLeft() < n) fail(raw_.at(where()) + "the file ends inside " + what);
    std::uint64_t bits = 0;
    for (size_t b = 0; b < n; ++b) {
      const size_t at = encoding_ == Encoding::Big ? b : n - 1 - b;
      bits = (bits << 8) | static_cast<unsigned char>(bytes_[pos_ + at]);
    }
    pos_ += n;
    if (!type.integer) return n == 4 ? floatOf(static_cast<std::uint32_t>(bits)) : doubleOf(bits);
    if (type.is_signed && n < 8 && (bits >> (8 * n - 1)) != 0)
      return static_cast<double>(static_cast<std::int64_t>(bits) - (std::int64_t{1} << (8 * n)));
    return static_cast<double>(bits);
  }

  static double floatOf(std::uint32_t bits) {
    float f = 0.0f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }
  static double doubleOf(std::uint64_t bits) {
    double d = 0.0;
    std::memcpy(&d, &bits, sizeof d);
    return d;
  }

  const RawMesh& raw_;
  const std::string& bytes_;
  Encoding encoding_;
  size_t pos_;
  TextLines lines_;
  std::int64_t line0_;
  std::vector<std::string_view> tokens_;
  size_t k_ = 0;
};

bool isIndexList(const Property& p) {
  return p.count_type.bytes > 0 && (p.name == "vertex_indices" || p.name == "vertex_index");
}

// Checks the header names a vertex element with x, y, z and a face element with an integer index list.
void checkHeader(const RawMesh& raw, const Header& header) {
  const auto named = [&](const char* name) {
    for (const Element& e : header.elements)
      if (e.name == name) return &e;
    fail(raw.file + ": the PLY header has no 'element " + std::string(name) + "'");
  };
  const Element* vertex = named("vertex");
  for (const char* axis : {"x", "y", "z"}) {
    const auto& ps = vertex->properties;
    if (std::none_of(ps.begin(), ps.end(),
                     [&](const Property& p) { return p.name == axis && p.count_type.bytes == 0; }))
      fail(raw.file + ": the PLY vertex element has no property '" + axis + "'");
  }
  const auto& fs = named("face")->properties;
  const auto list = std::find_if(fs.begin(), fs.end(), isIndexList);
  if (list == fs.end()) fail(raw.file + ": the PLY face element has no list 'vertex_indices'");
  if (!list->type.integer) fail(raw.file + ": the PLY face indices must have an integer type");
}

// Binary data: every element's fixed part (its scalars and list counts) must fit in the bytes left.
void checkFits(const RawMesh& raw, const Header& header, size_t bytes_left) {
  long double need = 0;
  for (const Element& e : header.elements) {
    int per = 0;
    for (const Property& p : e.properties) per += p.count_type.bytes > 0 ? p.count_type.bytes : p.type.bytes;
    need += static_cast<long double>(per) * static_cast<long double>(e.count);
    if (need > static_cast<long double>(bytes_left))
      fail(raw.at(static_cast<std::int64_t>(header.data_offset)) + "the header declares " + std::to_string(e.count) +
           " " + e.name + " elements (" + std::to_string(per) + " bytes each at least) but only " +
           std::to_string(bytes_left) + " bytes follow the header");
  }
}

struct Target {
  bool vertex = false, face = false;
  long long vertices = 0;  // declared, for the face indices
  double scale = 1.0;
  std::vector<int> polygon;
  std::vector<double> corner_texcoords;  // a face's "texcoord" list
  bool has_corner_texcoords = false;     // the face element has one
};

// Which texture coordinate a vertex property holds: 0 (u), 1 (v) or -1 (none).
int texCoordAxis(const std::string& name) {
  if (name == "s" || name == "texture_u" || name == "u") return 0;
  if (name == "t" || name == "texture_v" || name == "v") return 1;
  return -1;
}

void readList(const RawMesh& raw, Values& values, const Property& p, const std::string& what, Target& target) {
  const double n = values.next(p.count_type, what);
  if (n < 0)
    fail(raw.at(values.where()) + what + ": negative list length " + std::to_string(static_cast<long long>(n)));
  const bool indices = target.face && isIndexList(p);
  const bool texcoords = target.face && p.name == "texcoord";
  if (indices && n < 3)
    fail(raw.at(values.where()) + what + " has " + std::to_string(static_cast<long long>(n)) +
         " vertices (at least 3)");
  if (indices) target.polygon.clear();
  if (texcoords) target.corner_texcoords.clear(), target.has_corner_texcoords = true;
  for (double j = 0; j < n; ++j) {
    const double v = values.next(p.type, what);
    if (texcoords) {
      if (!std::isfinite(v)) fail(raw.at(values.where()) + what + " has a non-finite texture coordinate");
      target.corner_texcoords.push_back(v);
    }
    if (!indices) continue;
    if (v < 0 || v >= static_cast<double>(target.vertices))
      fail(raw.at(values.where()) + what + " has index " + std::to_string(static_cast<long long>(v)) +
           " but there are " + std::to_string(target.vertices) + " vertices");
    target.polygon.push_back(static_cast<int>(v));
  }
}

// A face's fan, and its corners' texture coordinates when its "texcoord" list has two per corner.
// `where` is the face's (as the other readers give it), `end` where its data ended (for the message).
void addFace(RawMesh& raw, Target& target, const std::string& what, std::int64_t where, std::int64_t end) {
  raw.addPolygon(target.polygon, where);
  if (!target.has_corner_texcoords) return;
  if (target.corner_texcoords.size() != 2 * target.polygon.size())
    fail(raw.at(end) + what + " has " + std::to_string(target.corner_texcoords.size()) + " texture coordinates for " +
         std::to_string(target.polygon.size()) + " corners (2 each)");
  std::vector<int> corners;
  for (size_t c = 0; c < target.polygon.size(); ++c) {
    corners.push_back(static_cast<int>(raw.corner_texcoords.size()));
    raw.corner_texcoords.emplace_back(target.corner_texcoords[2 * c], target.corner_texcoords[2 * c + 1]);
  }
  raw.addPolygonTexCoords(corners);
}

void readElement(RawMesh& raw, Values& values, const Element& e, Target& target) {
  if (e.properties.empty()) return;  // nothing to read, however many
  for (long long i = 0; i < e.count; ++i) {
    const std::int64_t where = values.where();
    const std::string what = e.name + " " + std::to_string(i);
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    for (const Property& prop : e.properties) {
      if (prop.count_type.bytes > 0) {
        readList(raw, values, prop, what, target);
        continue;
      }
      const double v = values.next(prop.type, what);
      if (target.vertex && prop.name.size() == 1 && prop.name[0] >= 'x' && prop.name[0] <= 'z')
        p[prop.name[0] - 'x'] = v;
      if (target.vertex && texCoordAxis(prop.name) >= 0) uv[texCoordAxis(prop.name)] = v;
    }
    if (target.vertex) {
      if (!p.allFinite()) fail(raw.at(where) + what + " has a non-finite coordinate");
      if (!uv.allFinite()) fail(raw.at(where) + what + " has a non-finite texture coordinate");
      raw.addPoint(p, target.scale, where);
      raw.texcoords.push_back(uv);
    }
    if (target.face) addFace(raw, target, what, where, values.where());
  }
}

// Per-vertex coordinates (the vertex element has both axes) when no face gave its corners'.
void vertexTexCoords(RawMesh& raw, const Element& vertex) {
  const auto has = [&](int axis) {
    return std::any_of(vertex.properties.begin(), vertex.properties.end(),
                       [&](const Property& p) { return p.count_type.bytes == 0 && texCoordAxis(p.name) == axis; });
  };
  if (!raw.triangle_texcoords.empty()) {
    raw.texcoords = std::move(raw.corner_texcoords);
  } else if (has(0) && has(1)) {
    raw.triangle_texcoords = raw.triangles;
  } else {
    raw.texcoords.clear();
  }
  raw.corner_texcoords.clear();
}

}  // namespace

RawMesh readPly(const std::filesystem::path& path, double scale) {
  const std::string bytes = readWholeFile(path);
  RawMesh raw = zeroBasedMesh(path);
  const Header header = parseHeader(raw, bytes);
  checkHeader(raw, header);
  Values values(raw, bytes, header);
  raw.binary = header.encoding != Encoding::Ascii;
  if (raw.binary) checkFits(raw, header, values.bytesLeft());
  long long vertices = 0;
  for (const Element& e : header.elements)
    if (e.name == "vertex") vertices = e.count;
  const Element* vertex = nullptr;
  for (const Element& e : header.elements) {
    Target target{e.name == "vertex", e.name == "face", vertices, scale, {}, {}, false};
    readElement(raw, values, e, target);
    if (e.name == "vertex") vertex = &e;
  }
  if (vertex != nullptr) vertexTexCoords(raw, *vertex);
  return raw;
}

}  // namespace incise::mesh::detail
