// What replay, record and bench share: a scenario's tissue, world and poses (incise::jobs's ScenarioRun, the
// one definition the C API and the Python module use too), and how a command gives up on bad input.
#pragma once

#include <string>

#include "incise/jobs/scenario_run.h"

namespace incise::apps {

using LoadedScenario = jobs::ScenarioRun;
using jobs::kTissueComment;
using jobs::loadScenarioRun;
using jobs::scenarioPoses;
using jobs::tissueHashText;
using jobs::traceTissueHash;

// Prints "incise <command>: <message>" to stderr and exits with code 2 (bad input or I/O).
[[noreturn]] void failWith(const char* command, const std::string& message);

}  // namespace incise::apps
