#include "json_reader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "incise/core/format.h"

namespace incise::sim::detail {

using core::formatNumber;
using nlohmann::json;

TextPosition positionOf(const std::string& text, std::size_t offset) {
  const std::size_t at = std::min(offset, text.size());
  TextPosition p;
  p.line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  const std::size_t line_start = at == 0 ? std::string::npos : text.rfind('\n', at - 1);
  p.column = at - (line_start == std::string::npos ? 0 : line_start + 1) + 1;
  return p;
}

json parseJsonFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ScenarioError(file.string() + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  try {
    return json::parse(s);
  } catch (const json::parse_error& e) {
    // nlohmann counts the byte it stopped at from 1; the position is that byte's.
    const TextPosition p = positionOf(s, e.byte == 0 ? 0 : e.byte - 1);
    throw ScenarioError(file.string() + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) +
                        ": JSON syntax error");
  } catch (const json::out_of_range& e) {
    // A number beyond double's range ("1e400"; found by tests/fuzz/fuzz_wrap_scenario): nlohmann says
    // "... number overflow parsing '1e400'" without a position, so the number's first occurrence is named.
    const std::string what = e.what();
    const std::size_t open = what.find('\''), close = what.rfind('\'');
    const std::string number = open < close ? what.substr(open + 1, close - open - 1) : "";
    const std::size_t at = number.empty() ? std::string::npos : s.find(number);
    const TextPosition p = positionOf(s, at == std::string::npos ? 0 : at);
    throw ScenarioError(file.string() + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) +
                        ": JSON number out of range" + (number.empty() ? "" : " '" + number + "'"));
  }
}

std::string keyPattern(std::string_view key_path) {
  std::string out;
  bool in_index = false;
  for (const char c : key_path) {
    if (c == '[') in_index = true, out += "[]";
    if (c == ']')
      in_index = false;
    else if (!in_index && c != '[')
      out += c;
  }
  return out;
}

JsonReader::JsonReader(std::filesystem::path file, const json& object, std::string key_path)
    : JsonReader(std::move(file), object, std::move(key_path), std::make_shared<KeyLog>()) {}

JsonReader::JsonReader(std::filesystem::path file, const json& object, std::string key_path,
                       std::shared_ptr<KeyLog> log)
    : file_(std::move(file)), object_(object), path_(std::move(key_path)), log_(std::move(log)) {
  if (!object_.is_object()) fail(path_.empty() ? "the document must be a JSON object" : "must be an object");
  KeyLog::Object& logged = log_->objects[path_];
  if (logged.present.empty())
    for (const auto& item : object_.items()) logged.present.push_back(item.key());
}

bool JsonReader::has(const char* key) const {
  log_->objects[path_].asked.insert(key);
  return object_.contains(key);
}

void JsonReader::fail(const std::string& message, const std::string& key) const {
  const std::string where = key.empty() ? path_ : join(key.c_str());
  throw ScenarioError(file_.string() + ": " + (where.empty() ? "" : where + ": ") + message);
}

JsonReader JsonReader::child(const char* key) const {
  if (!has(key)) return JsonReader(file_, json::object(), join(key), log_);
  return JsonReader(file_, object_.at(key), join(key), log_);
}

JsonReader JsonReader::requiredChild(const char* key) const {
  if (!has(key)) fail("is missing", key);
  return child(key);
}

std::vector<JsonReader> JsonReader::objects(const char* key) const {
  if (!has(key) || !object_.at(key).is_array() || object_.at(key).empty()) fail("must be a non-empty array", key);
  std::vector<JsonReader> list;
  const json& array = object_.at(key);
  for (std::size_t k = 0; k < array.size(); ++k)
    list.push_back(JsonReader(file_, array[k], join(key) + "[" + std::to_string(k) + "]", log_));
  return list;
}

double JsonReader::number(const char* key, double fallback, double lo, double hi) const {
  if (!has(key)) return fallback;
  const json& v = object_.at(key);
  if (!v.is_number()) fail("must be a number, got " + v.dump(), key);
  const double x = v.get<double>();
  if (!(x >= lo && x <= hi))
    fail(formatNumber(x) + " is outside [" + formatNumber(lo) + ", " + formatNumber(hi) + "]", key);
  return x;
}

int JsonReader::integer(const char* key, int fallback, int lo, int hi) const {
  if (!has(key)) return fallback;
  const json& v = object_.at(key);
  if (!v.is_number_integer()) fail("must be an integer, got " + v.dump(), key);
  // An unsigned value beyond long long would wrap in get<long long>(): it is out of any int range anyway.
  if (v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(hi))
    fail(v.dump() + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", key);
  const long long x = v.get<long long>();
  if (x < lo || x > hi)
    fail(std::to_string(x) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", key);
  return static_cast<int>(x);
}

bool JsonReader::boolean(const char* key, bool fallback) const {
  if (!has(key)) return fallback;
  if (!object_.at(key).is_boolean()) fail("must be true or false", key);
  return object_.at(key).get<bool>();
}

std::string JsonReader::text(const char* key, const char* fallback) const {
  if (!has(key)) {
    if (fallback) return fallback;
    fail("is missing", key);
  }
  const json& v = object_.at(key);
  if (!v.is_string()) fail("must be a string, got " + v.dump(), key);
  return v.get<std::string>();
}

std::string JsonReader::choice(const char* key, const char* fallback, const std::vector<std::string>& choices) const {
  const std::string value = text(key, fallback);
  if (std::find(choices.begin(), choices.end(), value) != choices.end()) return value;
  std::string list;
  for (std::size_t i = 0; i < choices.size(); ++i)
    list += (i == 0 ? "\"" : (i + 1 == choices.size() ? " or \"" : ", \"")) + choices[i] + "\"";
  fail("must be " + list + ", got \"" + value + "\"", key);
}

Eigen::Vector3d JsonReader::vector(const char* key, const Eigen::Vector3d& fallback) const {
  if (!has(key)) return fallback;
  const json& v = object_.at(key);
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    fail("must be an array of 3 numbers, got " + v.dump(), key);
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

std::vector<double> JsonReader::numbers(const char* key, std::size_t count, const std::vector<double>& fallback) const {
  if (!has(key)) return fallback;
  const json& v = object_.at(key);
  const bool ok = v.is_array() && v.size() == count && std::all_of(v.begin(), v.end(), [](const json& x) {
                    return x.is_number() && std::isfinite(x.get<double>());
                  });
  if (!ok) fail("must be an array of " + std::to_string(count) + " finite numbers, got " + v.dump(), key);
  std::vector<double> out;
  for (const json& x : v) out.push_back(x.get<double>());
  return out;
}

std::filesystem::path JsonReader::file(const char* key) const {
  const std::filesystem::path p = file_.parent_path() / text(key, nullptr);
  std::error_code error;  // a name the system refuses (too long, ...) is a bad value, not a crash
  const bool found = std::filesystem::exists(p, error);
  if (error) fail("file " + p.string() + " cannot be looked up: " + error.message(), key);
  if (!found) fail("file " + p.string() + " does not exist", key);
  return p;
}

namespace {

// Edit distance with adjacent transpositions (optimal string alignment): "budegt" is 1 from "budget".
std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

std::string joined(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

// The key of `known` under `parent` (a pattern) nearest to `key`, when it is near enough to be a slip.
std::string nearestKey(std::span<const std::string_view> known, const std::string& parent, const std::string& key) {
  const std::string prefix = parent.empty() ? "" : parent + ".";
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, key.size() / 3) + 1;
  for (const std::string_view k : known) {
    if (k.substr(0, prefix.size()) != prefix) continue;
    const std::string_view name = k.substr(prefix.size());
    if (name.find('.') != std::string_view::npos || name.find('[') != std::string_view::npos) continue;
    const std::size_t distance = editDistance(key, name);
    if (distance < best_distance) best_distance = distance, best = std::string(name);
  }
  return best;
}

}  // namespace

void JsonReader::refuseUnknownKeys(std::span<const std::string_view> known, bool unlisted_only) const {
  const auto listed = [&known](const std::string& pattern) {
    return std::find(known.begin(), known.end(), pattern) != known.end();
  };
  for (const auto& [path, object] : log_->objects)
    for (const std::string& key : object.asked)
      if (!listed(keyPattern(joined(path, key))))
        throw std::logic_error("scenario reader: " + joined(path, key) + " is read but not in the list of keys");
  for (const auto& [path, object] : log_->objects)
    for (const std::string& key : object.present) {
      if (object.asked.count(key)) continue;
      const std::string where = joined(path, key), pattern = keyPattern(where);
      if (listed(pattern) && unlisted_only) continue;
      if (listed(pattern))
        throw ScenarioError(file_.string() + ": " + where + ": has no effect here (it belongs to another kind of " +
                            (path.empty() ? std::string("scenario") : path) + "; see docs/scenarios.md)");
      const std::string nearest = nearestKey(known, keyPattern(path), key);
      throw ScenarioError(file_.string() + ": " + where + ": unknown key" +
                          (nearest.empty() ? "" : "; did you mean " + joined(path, nearest) + "?"));
    }
}

}  // namespace incise::sim::detail
