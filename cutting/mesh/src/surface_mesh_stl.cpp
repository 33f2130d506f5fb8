// The STL reader (surface_mesh_internal.h), binary and ASCII. Binary when the size is exactly 84 + 50 * the
// triangle count at byte 80 (so a binary file whose 80-byte header begins with "solid" is still binary);
// ASCII when the text begins with "solid" and holds no NUL byte; otherwise a binary file of the wrong size,
// refused with both sizes. Facet normals and the attribute bytes are ignored. STL repeats each corner, so
// exactly equal positions are welded into one vertex (numbered in order of first use) before the checks.
// Errors name the byte offset of a binary triangle or file:line of an ASCII one.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "surface_mesh_internal.h"

namespace incise::mesh::detail {

namespace {

constexpr std::uint64_t kHeaderBytes = 84, kTriangleBytes = 50;

std::uint32_t littleEndian32(const std::string& bytes, size_t at) {
  std::uint32_t v = 0;
  for (int b = 3; b >= 0; --b) v = (v << 8) | static_cast<unsigned char>(bytes[at + static_cast<size_t>(b)]);
  return v;
}

float littleEndianFloat(const std::string& bytes, size_t at) {
  const std::uint32_t bits = littleEndian32(bytes, at);
  float f = 0.0f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

void readBinary(RawMesh& raw, const std::string& bytes, std::uint32_t count, double scale) {
  raw.binary = true;
  raw.points.reserve(3 * static_cast<size_t>(count));  // the size was checked against the count
  for (std::uint32_t t = 0; t < count; ++t) {
    const size_t offset = kHeaderBytes + kTriangleBytes * t;
    for (size_t corner = 0; corner < 3; ++corner) {
      Eigen::Vector3d p;
      for (size_t a = 0; a < 3; ++a)
        p[static_cast<Eigen::Index>(a)] = littleEndianFloat(bytes, offset + 12 * (corner + 1) + 4 * a);
      if (!p.allFinite())
        fail(raw.at(static_cast<std::int64_t>(offset)) + "triangle " + std::to_string(t) +
             " has a non-finite coordinate");
      raw.addPoint(p, scale, static_cast<std::int64_t>(offset));
    }
    const int first = static_cast<int>(3 * t);
    raw.triangles.push_back({first, first + 1, first + 2});
    raw.triangle_lines.push_back(static_cast<std::int64_t>(offset));
  }
}

// Expects the next tokens to be `words` (on any lines); the values after "normal" and "vertex" are read
// by the caller.
void expect(const RawMesh& raw, TextLines& lines, std::vector<std::string_view>& tokens, size_t& k,
            std::string_view word) {
  while (k >= tokens.size()) {
    if (!lines.nextTokens(tokens, false))
      fail(raw.file + ": the file ends where '" + std::string(word) + "' was expected (line " +
           std::to_string(lines.line()) + ")");
    k = 0;
  }
  if (tokens[k] != word)
    fail(raw.at(lines.line()) + "expected '" + std::string(word) + "', got '" + std::string(tokens[k]) + "'");
  ++k;
}

// One "facet normal nx ny nz / outer loop / vertex x y z (x3) / endloop / endfacet", after "facet".
void readFacet(RawMesh& raw, TextLines& lines, std::vector<std::string_view>& tokens, size_t& k, double scale) {
  expect(raw, lines, tokens, k, "normal");
  k += 3;  // the normal, ignored (a missing one shows as the next 'expected')
  expect(raw, lines, tokens, k, "outer");
  expect(raw, lines, tokens, k, "loop");
  const std::int64_t line = lines.line();
  for (int corner = 0; corner < 3; ++corner) {
    expect(raw, lines, tokens, k, "vertex");
    const std::string where = raw.at(lines.line());
    if (tokens.size() < k + 3) fail(where + "expected 3 coordinates after 'vertex'");
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = parseCoordinate(tokens[k++], where);
    raw.addPoint(p, scale, lines.line());
  }
  expect(raw, lines, tokens, k, "endloop");
  expect(raw, lines, tokens, k, "endfacet");
  const int first = static_cast<int>(raw.points.size()) - 3;
  raw.triangles.push_back({first, first + 1, first + 2});
  raw.triangle_lines.push_back(line);
}

void readAscii(RawMesh& raw, const std::string& text, double scale) {
  TextLines lines(text);
  std::vector<std::string_view> tokens;
  while (lines.nextTokens(tokens, false)) {  // one "solid name ... endsolid name" after another
    if (tokens[0] != "solid") fail(raw.at(lines.line()) + "expected 'solid', got '" + std::string(tokens[0]) + "'");
    size_t k = tokens.size();  // the solid's name is ignored
    for (;;) {
      while (k >= tokens.size()) {
        if (!lines.nextTokens(tokens, false)) fail(raw.file + ": the file ends before 'endsolid'");
        k = 0;
      }
      if (tokens[k] == "endsolid") break;
      expect(raw, lines, tokens, k, "facet");
      readFacet(raw, lines, tokens, k, scale);
    }
  }
}

// Merges exactly equal positions; the welded vertices are numbered in order of first use.
void weld(RawMesh& raw) {
  const auto& p = raw.points;
  std::vector<int> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  auto key = [&](int i) {
    return std::make_tuple(p[static_cast<size_t>(i)].x(), p[static_cast<size_t>(i)].y(), p[static_cast<size_t>(i)].z());
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  std::vector<int> first_use(p.size());  // each point -> the first point with its position
  for (size_t i = 0; i < order.size(); ++i)
    first_use[static_cast<size_t>(order[i])] =
        (i > 0 && key(order[i]) == key(order[i - 1])) ? first_use[static_cast<size_t>(order[i - 1])] : order[i];
  std::vector<int> renumber(p.size(), -1);
  RawMesh welded;
  for (size_t i = 0; i < p.size(); ++i) {
    if (first_use[i] != static_cast<int>(i)) continue;
    renumber[i] = static_cast<int>(welded.points.size());
    welded.points.push_back(p[i]);
    welded.point_lines.push_back(raw.point_lines[i]);
  }
  for (auto& triangle : raw.triangles)
    for (int& v : triangle) v = renumber[static_cast<size_t>(first_use[static_cast<size_t>(v)])];
  raw.points = std::move(welded.points);
  raw.point_lines = std::move(welded.point_lines);
}

}  // namespace

RawMesh readStl(const std::filesystem::path& path, double scale) {
  const std::string bytes = readWholeFile(path);
  RawMesh raw = zeroBasedMesh(path, " (vertex numbers 0-based, in order of first use after welding equal positions)");
  const std::uint64_t size = bytes.size();
  const std::uint64_t count = size >= kHeaderBytes ? littleEndian32(bytes, 80) : 0;
  if (size >= kHeaderBytes && size == kHeaderBytes + kTriangleBytes * count) {
    readBinary(raw, bytes, static_cast<std::uint32_t>(count), scale);
  } else if (bytes.compare(0, 5, "solid") == 0 && bytes.find('\0') == std::string::npos) {
    readAscii(raw, bytes, scale);
  } else if (size < kHeaderBytes) {
    fail(raw.file + ": not ASCII STL (no 'solid') and too short for binary STL (" + std::to_string(size) +
         " bytes; the header and count take 84)");
  } else {
    fail(raw.file + ": binary STL declares " + std::to_string(count) + " triangles (" +
         std::to_string(kHeaderBytes + kTriangleBytes * count) + " bytes) but the file has " + std::to_string(size) +
         " bytes");
  }
  weld(raw);
  return raw;
}

}  // namespace incise::mesh::detail
