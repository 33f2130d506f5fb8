// Private to sim: reading a scenario's {"kind": "hid-recording"} pose source (scenario.h; the keys are in
// docs/scenarios.md). Failure: ScenarioError naming the file and the key path.
#pragma once

#include "incise/sim/scenario.h"
#include "json_reader.h"

namespace incise::sim::detail {

HidRecordingSource readHidRecordingSource(const JsonReader& source);

}  // namespace incise::sim::detail
