// What the mesh readers share (surface_mesh_internal.h): the whole file, lines and tokens, numbers, and
// the triangle list's points and polygon fans.
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>

#include "incise/core/format.h"
#include "surface_mesh_internal.h"

namespace incise::mesh::detail {

RawMesh zeroBasedMesh(const std::filesystem::path& path, std::string vertex_note) {
  RawMesh raw;
  raw.file = path.string();
  raw.index_base = 0;
  raw.vertex_note = std::move(vertex_note);
  return raw;
}

std::string readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(path.string() + ": read error");
  return text;
}

void splitTokens(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) tokens.push_back(line.substr(i, j - i));
    i = j;
  }
}

double parseCoordinate(std::string_view token, const std::string& where) {
  std::string_view digits = token;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  const std::string quoted = std::string("'").append(token).append("'");  // not "'" + ...: GCC 12 -Wrestrict, PR 105651
  if (ec == std::errc::result_out_of_range) fail(where + "coordinate " + quoted + " is out of range");
  if (ec != std::errc() || end != digits.data() + digits.size())
    fail(where + "coordinate " + quoted + " is not a number");
  if (!std::isfinite(value)) fail(where + "coordinate " + quoted + " is not finite");
  return value;
}

std::optional<long long> parseInteger(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  long long value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size() || token.empty()) return std::nullopt;
  return value;
}

bool TextLines::nextTokens(std::vector<std::string_view>& tokens, bool comments) {
  tokens.clear();
  while (tokens.empty() && pos_ < text_.size()) {
    size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++line_;
    if (comments) line = line.substr(0, line.find('#'));
    splitTokens(line, tokens);
  }
  return !tokens.empty();
}

void RawMesh::addPoint(const Eigen::Vector3d& p, double scale, std::int64_t where) {
  const Eigen::Vector3d scaled = p * scale;
  if (!scaled.allFinite()) fail(at(where) + "coordinate overflows after scaling by " + core::formatNumber(scale));
  points.push_back(scaled);
  point_lines.push_back(where);
}

void RawMesh::addPolygon(const std::vector<int>& polygon, std::int64_t where) {
  for (size_t k = 2; k < polygon.size(); ++k) {  // fan: (first, previous, next)
    triangles.push_back({polygon[0], polygon[k - 1], polygon[k]});
    triangle_lines.push_back(where);
  }
}

void RawMesh::addPolygonTexCoords(const std::vector<int>& polygon_texcoords) {
  for (size_t k = 2; k < polygon_texcoords.size(); ++k)
    triangle_texcoords.push_back({polygon_texcoords[0], polygon_texcoords[k - 1], polygon_texcoords[k]});
}

}  // namespace incise::mesh::detail
