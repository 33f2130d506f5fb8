// The files the scenario harnesses' JSON may name (fuzz_scenario.cpp, fuzz_wrap_scenario.cpp): tiny valid
// ones, written once into the scratch folder, under the names the seed scenarios use (relative to
// scratch() / "scenarios", where the input is written): meshes/tiny.obj and tiny.off (a regular octahedron,
// closed and outward-facing), traces/tiny.csv (two samples), hid/tiny.hid (a one-report recording),
// hid/descriptors/tiny.txt (a one-byte-report descriptor in hex), generate/tiny.json (a strokes scenario).
// The shipped meshes and recordings are far larger; the loaders only need something valid to read.
// Also the harnesses' shared body (runScenario) and their LLVMFuzzerInitialize: include this header from
// one harness file only (each harness is its own program).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_input.h"
#include "incise/sim/scenario_error.h"

namespace incise::fuzz {

inline void writeScenarioFiles() {
  const test::TempDir& d = scratch();
  d.write("scenarios/meshes/tiny.obj",
          "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
          "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n");
  d.write("scenarios/meshes/tiny.off",
          "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
          "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n");
  d.write("scenarios/traces/tiny.csv",
          "time_s,tip_x_m,tip_y_m,tip_z_m,q_w,q_x,q_y,q_z,buttons,pressure\n"
          "0,0,0.01,0,1,0,0,0,0,\n0.001,0,0,0,1,0,0,0,1,\n");
  // A mouse-like descriptor: usage page 1, usage 2, collection, 8 one-bit buttons, end collection.
  const std::string descriptor = "05 01 09 02 a1 01 05 09 19 01 29 08 15 00 25 01 75 01 95 08 81 02 c0";
  d.write("scenarios/hid/descriptors/tiny.txt", "# a mouse's buttons\n" + descriptor + "\n");
  d.write("scenarios/hid/tiny.hid", "R: 23 " + descriptor + "\nN: tiny\nI: 3 056a 0357\nE: 000000.000000 1 01\n");
  d.write("scenarios/generate/tiny.json",
          "{\"tissue\": {\"mesh\": \"../meshes/tiny.obj\"}, \"pose_source\": {\"kind\": \"strokes\", \"strokes\": "
          "[{\"start_m\": [0, 0.02, 0]}]}}\n");
}

// Writes the input to scratch() / name and loads it with `load`; ScenarioError, the loaders' documented
// failure, is caught, anything else escapes to libFuzzer as a finding.
template <class Load>
int runScenario(const std::uint8_t* data, std::size_t size, const std::string& name, Load load) {
  const std::filesystem::path path = writeInput(data, size, name);
  try {
    load(path);
  } catch (const sim::ScenarioError&) {
  }
  return 0;
}

}  // namespace incise::fuzz

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  incise::fuzz::writeScenarioFiles();
  return 0;
}
