#include "score_plots.h"

#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "incise/core/format.h"

extern char** environ;

namespace incise::apps::training {

namespace {

using core::formatNumber;

int runGnuplot(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, "gnuplot", nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void writeData(const sim::Score& score, const std::filesystem::path& bins, const std::filesystem::path& frames) {
  std::ofstream b(bins);
  for (const sim::PlanBin& bin : score.plan.bins) {
    // Uncut bins are a gap in the lines (gnuplot's blank value).
    b << formatNumber(1e3 * bin.s_m) << ' ' << (bin.cut ? formatNumber(1e3 * bin.lateral_m) : "NaN") << ' '
      << (bin.cut ? formatNumber(1e3 * bin.depth_m) : "NaN") << ' '
      << (bin.blade_seen ? formatNumber(1e3 * bin.blade_depth_m) : "NaN") << '\n';
  }
  std::ofstream f(frames);
  const sim::ScoreFrame* previous = nullptr;
  for (const sim::ScoreFrame& frame : score.frames_seen) {
    if (!frame.new_pose) continue;
    const double dt_s = previous ? frame.t_s - previous->t_s : 0.0;
    const double speed = dt_s > 0.0 ? (frame.tip_m - previous->tip_m).norm() / dt_s : 0.0;
    f << formatNumber(frame.t_s) << ' ' << formatNumber(1e3 * speed) << ' ' << formatNumber(frame.force_N) << '\n';
    previous = &frame;
  }
  if (!b || !f) throw std::runtime_error("cannot write the plot data beside " + bins.string());
}

std::string quoted(const std::filesystem::path& p) {
  std::string q(1, '\'');  // built in steps: GCC 12's -Wrestrict misfires on "'" + s + "'"
  q.append(p.string()).push_back('\'');
  return q;
}

std::string script(const sim::Score& s, const std::filesystem::path& bins, const std::filesystem::path& frames,
                   const std::filesystem::path& out) {
  const bool plan = s.has_plan;
  std::string g = "set terminal pngcairo size 1200," + std::string(plan ? "900" : "450") + " font ',10'\n";
  g += "set output " + quoted(out) + "\nset datafile missing 'NaN'\nset grid\n";
  g += "set multiplot layout " + std::string(plan ? "2,2" : "1,2") + " title '" + s.scenario + "'\n";
  if (plan) {
    const std::string lat = formatNumber(1e3 * s.plan.lateral_tolerance_m);
    const std::string depth = formatNumber(1e3 * s.plan.target_depth_m);
    const std::string dtol = formatNumber(1e3 * s.plan.depth_tolerance_m);
    const std::string lat_range = formatNumber(2.5 * 1e3 * s.plan.lateral_tolerance_m);
    g += "set title 'lateral deviation along the plan'\nset xlabel 'along the plan (mm)'\nset ylabel 'mm'\n";
    g += "set yrange [-" + lat_range + ":" + lat_range + "]\n";
    g += "plot " + quoted(bins) + " using 1:(-" + lat + "):(" + lat +
         ") with filledcurves fc rgb '#d0f0d0' title 'tolerance', " + quoted(bins) +
         " using 1:2 with lines lw 2 lc rgb '#1060c0' title 'cut'\n";
    g += "set title 'depth along the plan'\nset yrange [0:" +
         formatNumber(1e3 * (1.5 * s.plan.target_depth_m + 2.0 * s.plan.depth_tolerance_m)) + "]\nplot " +
         quoted(bins) + " using 1:(" + depth + "-" + dtol + "):(" + depth + "+" + dtol +
         ") with filledcurves fc rgb '#d0f0d0' title 'target +/- tolerance', " + quoted(bins) +
         " using 1:3 with lines lw 2 lc rgb '#c04010' title 'cut depth', " + quoted(bins) +
         " using 1:4 with lines dt 2 lc rgb '#404040' title 'blade tip depth'\n";
  }
  g += "set title 'tip speed'\nset xlabel 'time (s)'\nset ylabel 'mm/s'\nset yrange [0:*]\nplot " + quoted(frames) +
       " using 1:2 with lines lc rgb '#1060c0' notitle\n";
  g += "set title 'force'\nset ylabel 'N'\nset yrange [0:" +
       formatNumber(1.2 * std::max(s.peak_force_N, s.force_threshold_N) + 0.1) + "]\nplot " + quoted(frames) +
       " using 1:3 with lines lc rgb '#c04010' notitle, " + formatNumber(s.force_threshold_N) +
       " with lines dt 2 lc rgb 'black' title 'threshold'\n";
  return g + "unset multiplot\nset output\n";
}

}  // namespace

bool gnuplotAvailable() { return runGnuplot({"gnuplot", "-e", "exit"}) == 0; }

void writeScorePlot(const sim::Score& score, const std::filesystem::path& png) {
  std::filesystem::path bins = png, frames = png, gp = png, tmp = png;
  bins += ".bins.tmp", frames += ".frames.tmp", gp += ".gp.tmp", tmp += ".tmp";
  const auto cleanUp = [&] {
    std::error_code ignored;
    for (const auto& p : {bins, frames, gp, tmp}) std::filesystem::remove(p, ignored);
  };
  try {
    writeData(score, bins, frames);
    std::ofstream(gp) << script(score, bins, frames, tmp);
    const int status = runGnuplot({"gnuplot", gp.string()});
    if (status != 0)
      throw std::runtime_error(png.string() + ": gnuplot failed (exit status " + std::to_string(status) + ")");
    std::filesystem::rename(tmp, png);
  } catch (...) {
    cleanUp();
    throw;
  }
  cleanUp();
}

}  // namespace incise::apps::training
