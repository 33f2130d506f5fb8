#include "json_output.h"

#include "incise/core/atomic_file.h"

namespace incise::apps {

void writeJsonAtomically(const nlohmann::json& document, const std::filesystem::path& path) {
  core::writeFileAtomically(path, document.dump(2) + "\n");
}

}  // namespace incise::apps
