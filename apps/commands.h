// The `incise` subcommands. Each registers its options on the CLI11 app and runs when chosen; a command
// returns the process exit code (0 success, 1 the job ran but a check failed, 2 bad input or I/O).
#pragma once

#include <CLI/CLI.hpp>

namespace incise::apps {

void addCutCommand(CLI::App& app);
void addReplayCommand(CLI::App& app);
void addRecordCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addWrapCommand(CLI::App& app);
void addHidCommand(CLI::App& app);
void addImportCommand(CLI::App& app);
void addViewCommand(CLI::App& app);
void addTrainCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addScoreCommand(CLI::App& app);

}  // namespace incise::apps
