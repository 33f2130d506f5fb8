// Private to sim: the one typed reader of incise's JSON inputs (replay scenarios, wrap scenarios). Parsing
// a file reports a syntax error as "file:line:column: JSON syntax error: <what>"; a JsonReader over one
// object reads typed values with a default and a range and names the file and the key path in every error
// ("file: tissue.tets.max_volume_m3: -1 is outside [0, 1]"). Every key a reader is asked about is logged, so
// that after the whole document is read refuseUnknownKeys() names a key nothing read ("file:
// tissue.materail: unknown key; did you mean tissue.material?").
// Threads: any (values only; readers of one document share its log: one thread per document). Cost: O(file
// size) to parse; O(log keys) per value. Failure: ScenarioError.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "incise/sim/scenario_error.h"

namespace incise::sim::detail {

// The document in `file`: throws ScenarioError "file: cannot open" or "file:line:column: JSON syntax error".
nlohmann::json parseJsonFile(const std::filesystem::path& file);

// Line and column (1-based) of byte `offset` in `text`.
struct TextPosition {
  std::size_t line = 1, column = 1;
};
TextPosition positionOf(const std::string& text, std::size_t offset);

// The keys of every object a document's readers visited, and those a read asked about (present or not).
struct KeyLog {
  struct Object {
    std::vector<std::string> present;  // the object's keys, in the document's (sorted) order
    std::set<std::string> asked;
  };
  std::map<std::string, Object> objects;  // by key path ("" for the root, "pose_source.strokes[1]")
};

// "pose_source.strokes[1].length_m" -> "pose_source.strokes[].length_m": a path as scenario key lists name it.
std::string keyPattern(std::string_view key_path);

class JsonReader {
 public:
  // `key_path` is the dotted path of `object` in the document ("" for the root). Throws unless `object` is
  // a JSON object.
  JsonReader(std::filesystem::path file, const nlohmann::json& object, std::string key_path);

  [[noreturn]] void fail(const std::string& message, const std::string& key = "") const;

  // Whether `key` is present; logs the key as read (every accessor below goes through here).
  bool has(const char* key) const;
  // The object under `key`; an empty object when the key is absent (its values take their defaults).
  JsonReader child(const char* key) const;
  // The object under `key`, which must be present.
  JsonReader requiredChild(const char* key) const;
  // Each object of the array under `key`, which must be present and non-empty; its entries' key paths
  // read "key[i]".
  std::vector<JsonReader> objects(const char* key) const;

  double number(const char* key, double fallback, double lo, double hi) const;
  int integer(const char* key, int fallback, int lo, int hi) const;
  bool boolean(const char* key, bool fallback) const;
  // nullptr as the fallback: the key is required.
  std::string text(const char* key, const char* fallback) const;
  // The text under `key`, which must be one of `choices` (the message lists them).
  std::string choice(const char* key, const char* fallback, const std::vector<std::string>& choices) const;
  Eigen::Vector3d vector(const char* key, const Eigen::Vector3d& fallback) const;
  // `count` numbers (an array of exactly that many), e.g. a quaternion or a row-major 3x3 matrix.
  std::vector<double> numbers(const char* key, std::size_t count, const std::vector<double>& fallback) const;
  // A path relative to the file's folder, which must exist.
  std::filesystem::path file(const char* key) const;
  // A path relative to the file's folder that need not exist yet (an output).
  std::filesystem::path outputPath(const char* key) const { return file_.parent_path() / text(key, nullptr); }

  const nlohmann::json& raw() const { return object_; }
  // After the document is read: throws ScenarioError for the first key (in path order) present in a visited
  // object that no read asked about, naming the nearest key of `known` (dotted patterns, arrays as "[]") at
  // that place, or saying that a known key has no effect in this document. With `unlisted_only` (reading
  // stopped at an error, so keys may be unread yet), only a key `known` does not list is refused: a
  // misspelt key is named before the error it caused. Throws std::logic_error when a read asked about a key
  // `known` does not list (the list and the reader disagree: a bug).
  void refuseUnknownKeys(std::span<const std::string_view> known, bool unlisted_only = false) const;
  const std::filesystem::path& filePath() const { return file_; }
  std::string join(const char* key) const { return path_.empty() ? key : path_ + "." + key; }

 private:
  std::filesystem::path file_;
  nlohmann::json object_;
  std::string path_;
  std::shared_ptr<KeyLog> log_;

  JsonReader(std::filesystem::path file, const nlohmann::json& object, std::string key_path,
             std::shared_ptr<KeyLog> log);
};

// `read(root)` over `root`, then the unknown-key check: a key nothing read is refused; when the read threw
// ScenarioError, a key no list names is refused instead of it (the error it probably caused).
template <typename Read>
auto readCheckingKeys(const JsonReader& root, std::span<const std::string_view> known, Read&& read) {
  try {
    auto result = read(root);
    root.refuseUnknownKeys(known);
    return result;
  } catch (const ScenarioError&) {
    root.refuseUnknownKeys(known, true);
    throw;
  }
}

}  // namespace incise::sim::detail
