// The `incise` subcommands of this group. Each registers its options on the CLI11 app and runs when chosen;
// a command returns the process exit code (0 success, 1 a check the user asked for failed, 2 bad input or I/O).
#pragma once

#include <CLI/CLI.hpp>

namespace incise::apps::training {

void addViewCommand(CLI::App& app);
void addTrainCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addScoreCommand(CLI::App& app);

}  // namespace incise::apps::training
