// incise: real-time surgical cutting by discontinuous free-form deformation. `incise --help` lists the
// commands; every command's --help lists its options.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "geometry/geometry_commands.h"
#include "hid/hid_commands.h"
#include "run/run_commands.h"
#include "training/training_commands.h"

int main(int argc, char** argv) {
  CLI::App app{"incise: real-time surgical cutting by discontinuous free-form deformation (DFFD)"};
  app.require_subcommand(1);
  incise::apps::run::addReplayCommand(app);
  incise::apps::run::addRecordCommand(app);
  incise::apps::run::addBenchCommand(app);
  incise::apps::run::addKeysCommand(app);
  incise::apps::geometry::addCutCommand(app);
  incise::apps::geometry::addWrapCommand(app);
  incise::apps::hid::addHidCommand(app);
  incise::apps::geometry::addImportCommand(app);
  incise::apps::training::addViewCommand(app);
  incise::apps::training::addTrainCommand(app);
  incise::apps::training::addRenderCommand(app);
  incise::apps::training::addScoreCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const std::exception& e) {  // a failure no command caught (out of memory, a file system error)
    std::fprintf(stderr, "incise: %s\n", e.what());
    return 2;
  }
  return 0;  // the chosen command's callback has run; it exits with its own code on failure
}
