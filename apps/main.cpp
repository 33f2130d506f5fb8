// incise: real-time surgical cutting by discontinuous free-form deformation. `incise --help` lists the
// commands; every command's --help lists its options.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"incise: real-time surgical cutting by discontinuous free-form deformation (DFFD)"};
  app.require_subcommand(1);
  incise::apps::addReplayCommand(app);
  incise::apps::addRecordCommand(app);
  incise::apps::addBenchCommand(app);
  incise::apps::addCutCommand(app);
  incise::apps::addWrapCommand(app);
  incise::apps::addHidCommand(app);
  incise::apps::addImportCommand(app);
  incise::apps::addViewCommand(app);
  incise::apps::addTrainCommand(app);
  incise::apps::addRenderCommand(app);
  incise::apps::addScoreCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return 0;  // the chosen command's callback has run; it exits with its own code on failure
}
