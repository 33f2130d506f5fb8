// `incise keys [--kind replay|wrap]`: every key a scenario file may hold, one dotted path per line
// ("tissue.tets.max_volume_m3"; entries of arrays of objects as "pose_source.strokes[].length_m"), as the
// scenario readers check them. docs/scenarios.md documents each; the docs test reads this list.
#include <cstdio>
#include <memory>
#include <set>
#include <string>

#include "incise/sim/scenario_keys.h"
#include "run_commands.h"

namespace incise::apps::run {

void addKeysCommand(CLI::App& app) {
  auto kind = std::make_shared<std::string>("all");
  CLI::App* cmd = app.add_subcommand("keys", "List every key a scenario file may hold (docs/scenarios.md)");
  cmd->add_option("--kind", *kind, "replay, wrap or all (default: all, each key once)")
      ->check(CLI::IsMember({"replay", "wrap", "all"}));
  cmd->callback([kind] {
    std::set<std::string_view> keys;
    if (*kind != "wrap")
      for (const std::string_view k : sim::replayScenarioKeys()) keys.insert(k);
    if (*kind != "replay")
      for (const std::string_view k : sim::wrapScenarioKeys()) keys.insert(k);
    for (const std::string_view k : keys) std::printf("%.*s\n", static_cast<int>(k.size()), k.data());
  });
}

}  // namespace incise::apps::run
