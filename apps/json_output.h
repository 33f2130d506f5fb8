// Writing a JSON document the way every incise output is written (cutting::writeFileAtomically: to
// path + ".tmp", then renamed), so a crash or a full disk never leaves half a file. Throws
// cutting::FileError (a std::runtime_error) naming the file.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "incise/cutting/surface_cutter_options.h"

namespace incise::apps {

void writeJsonAtomically(const nlohmann::json& document, const std::filesystem::path& path);

// Per incision, in order: {"stroke_length_m", "groove_length_m"} (cutting::IncisionFigures).
nlohmann::json incisionFiguresJson(const std::vector<cutting::IncisionFigures>& figures);

// Sums over the incisions of their groove and stroke lengths (metres).
double totalGroove_m(const std::vector<cutting::IncisionFigures>& figures);
double totalStroke_m(const std::vector<cutting::IncisionFigures>& figures);

// p50, p99, max and mean of a list of durations in microseconds (nearest rank).
nlohmann::json timingSummary(std::vector<double> values_us);

}  // namespace incise::apps
