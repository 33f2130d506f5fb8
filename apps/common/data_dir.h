// Where the `incise` tool finds its shipped data (the scenarios, with their meshes and traces): the
// default scenario of replay/record/bench and the default mesh of cut.
// Search order: the INCISE_SCENARIOS environment variable (a folder); the installed copy beside the
// executable (<prefix>/bin/incise -> <prefix>/share/incise/scenarios, put there by `cmake --install`);
// the source tree the executable was built from (a build that was not installed). The first folder that
// holds bunny-straight.json wins.
// Threads: any. Cost: a few stat calls. Failure: scenariosDir() throws std::runtime_error listing the
// folders it tried.
#pragma once

#include <filesystem>
#include <string>

namespace incise::apps {

std::filesystem::path scenariosDir();
// scenariosDir() / name, as a string (for option defaults).
std::string shippedFile(const std::string& name);

}  // namespace incise::apps
