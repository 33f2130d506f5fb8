// The fuzz harnesses' shared plumbing: the loaders under test read files, so each input is written to a
// file in the process's own scratch folder (one per process, removed at exit; libFuzzer's -jobs and -fork
// workers are separate processes) and read back from there.
// Threads: libFuzzer calls a harness from one thread. Failure: std::filesystem::filesystem_error if the
// scratch folder cannot be made (the harness then stops: not a finding).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "support/temp_dir.h"

namespace incise::fuzz {

// The process's scratch folder.
inline const test::TempDir& scratch() {
  static const test::TempDir dir;
  return dir;
}

// The bytes as a string (a loader's text, a file's content).
inline std::string asText(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Writes the input to scratch() / name (folders made as needed) and returns the file's path.
inline std::filesystem::path writeInput(const std::uint8_t* data, std::size_t size, const std::string& name) {
  return scratch().write(name, asText(data, size));
}

}  // namespace incise::fuzz
