// Writing a JSON document the way every incise output is written (core::writeFileAtomically: to
// path + ".tmp", then renamed), so a crash or a full disk never leaves half a file. Throws
// core::FileError (a std::runtime_error) naming the file.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "incise/incision/surface_cutter_options.h"

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

// Per incision, in order: {"stroke_length_m", "groove_length_m"} (incision::IncisionFigures).
// Also where the groove runs along the stroke, the lattice columns that held no vertex, and the shortfall
// with its sentence ("why", empty when the groove is as long as the stroke).
nlohmann::json incisionFiguresJson(const std::vector<incision::IncisionFigures>& figures);
// What went wrong with the cut, for a report's failure field: the cutter's internal failure, else the first
// incision whose groove fell short of its stroke ("incision 2 of 3: a groove of ..."), else "".
std::string cutFailure(const incision::CutStats& stats);

// Sums over the incisions of their groove and stroke lengths (metres).
double totalGroove_m(const std::vector<incision::IncisionFigures>& figures);
double totalStroke_m(const std::vector<incision::IncisionFigures>& figures);

// p50, p99, max and mean of a list of durations in microseconds (nearest rank).
nlohmann::json timingSummary(std::vector<double> values_us);

}  // namespace incise::apps
