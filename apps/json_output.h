// Writing a JSON document the way every incise output is written (cutting::writeFileAtomically: to
// path + ".tmp", then renamed), so a crash or a full disk never leaves half a file. Throws
// cutting::FileError (a std::runtime_error) naming the file.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

namespace incise::apps {

void writeJsonAtomically(const nlohmann::json& document, const std::filesystem::path& path);

// p50, p99, max and mean of a list of durations in microseconds (nearest rank).
nlohmann::json timingSummary(std::vector<double> values_us);

}  // namespace incise::apps
