// The plots of `incise score --plots DIR` through gnuplot (Debian's gnuplot-nox; its pngcairo terminal):
// for a session against a plan, the lateral deviation and the depth along the plan with the tolerance
// bands, and the tip's speed and the force over time (with the force threshold); without a plan, speed and
// force only. The data go to temporary files beside the PNG, removed afterwards; the PNG is written as
// NAME.png.tmp and renamed: complete or absent.
// Threads: the caller's. Cost: a gnuplot process per picture (~0.2 s). Failure: std::runtime_error naming
// the file, or gnuplot's exit status (its stderr is passed through).
#pragma once

#include <filesystem>
#include <string>

#include "incise/jobs/score_traces.h"
#include "incise/sim/score.h"

namespace incise::apps::training {

// True when a `gnuplot` is on the PATH (checked before any work: exit 2 without one).
bool gnuplotAvailable();
void writeScorePlot(const sim::Score& score, const std::filesystem::path& png);
// A trace's line as `incise score` prints it (and `incise train` writes it): incise::jobs's.
using jobs::scoreLine;

}  // namespace incise::apps::training
