// The `incise` subcommands of this group. Each registers its options on the CLI11 app and runs when chosen;
// a command returns the process exit code (0 success, 1 a check the user asked for failed, 2 bad input or I/O).
#pragma once

#include <CLI/CLI.hpp>

namespace incise::apps::run {

void addReplayCommand(CLI::App& app);
void addRecordCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addKeysCommand(CLI::App& app);

}  // namespace incise::apps::run
