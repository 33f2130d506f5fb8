// Writing a JSON document the way every incise output is written (core::writeFileAtomically: to
// path + ".tmp", then renamed), so a crash or a full disk never leaves half a file. Throws
// core::FileError (a std::runtime_error) naming the file.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "incise/jobs/run_report.h"

namespace incise::apps {

void writeJsonAtomically(const nlohmann::json& document, const std::filesystem::path& path);

// For outputs written by a stream writer (a trace, a hid-recorder file): `write(tmp)` writes and closes
// `path`.tmp, which is then renamed onto `path`; on any exception the .tmp is removed and the exception
// rethrown. So the output is complete or absent.
template <typename Write>
void writeThroughTemporary(const std::filesystem::path& path, Write&& write) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  try {
    write(tmp);
    std::filesystem::rename(tmp, path);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
}

// The run's documents' pieces (incise::jobs's, shared with the C API and the Python module).
using jobs::cutFailure;
using jobs::incisionFiguresJson;
using jobs::timingSummary;
using jobs::totalGroove_m;
using jobs::totalStroke_m;

}  // namespace incise::apps
