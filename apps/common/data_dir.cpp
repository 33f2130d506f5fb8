#include "data_dir.h"

#include <cstdlib>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace incise::apps {

namespace {

bool holdsScenarios(const std::filesystem::path& dir) {
  std::error_code ignored;
  return std::filesystem::is_regular_file(dir / "bunny-straight.json", ignored);
}

std::filesystem::path executableDir() {
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::filesystem::path() : exe.parent_path();
}

}  // namespace

std::filesystem::path scenariosDir() {
  std::vector<std::filesystem::path> tried;
  if (const char* env = std::getenv("INCISE_SCENARIOS"); env && *env) tried.emplace_back(env);
  if (const std::filesystem::path bin = executableDir(); !bin.empty())
    tried.push_back((bin / INCISE_SCENARIOS_FROM_BIN).lexically_normal());
  tried.emplace_back(INCISE_SCENARIOS_SOURCE_DIR);
  for (const std::filesystem::path& dir : tried)
    if (holdsScenarios(dir)) return dir;
  std::string list;
  for (const std::filesystem::path& dir : tried) list += (list.empty() ? "" : ", ") + dir.string();
  throw std::runtime_error("cannot find incise's scenarios (tried " + list +
                           "); set INCISE_SCENARIOS to the scenarios folder or name the file");
}

std::string shippedFile(const std::string& name) {
  try {
    return (scenariosDir() / name).string();
  } catch (const std::runtime_error&) {
    return name;  // an option default only: using it reports the missing file by name
  }
}

}  // namespace incise::apps
