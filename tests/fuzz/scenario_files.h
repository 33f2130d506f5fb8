// The files the scenario harnesses' JSON may name (fuzz_scenario.cpp, fuzz_wrap_scenario.cpp): tiny valid
// ones, written once into the scratch folder, under the names the seed scenarios use (relative to
// scratch() / "scenarios", where the input is written): meshes/tiny.obj and tiny.off (a regular octahedron,
// closed and outward-facing), traces/tiny.csv (two samples), hid/tiny.hid (a one-report recording),
// hid/descriptors/tiny.txt (a one-byte-report descriptor in hex), generate/tiny.json (a strokes scenario),
// textures/tiny.png (one skin-coloured pixel).
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
  d.write("scenarios/textures/tiny.png",
          std::string("\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x01\x00\x00"
                      "\x00\x01\x08\x02\x00\x00\x00\x90\x77\x53\xde\x00\x00\x00\x0c\x49\x44\x41\x54\x78\x9c"
                      "\x63\x78\xb7\x63\x1e\x00\x04\xdc\x02\x45\xaa\x9c\xca\x9b\x00\x00\x00\x00\x49\x45\x4e\x44"
                      "\xae\x42\x60\x82",
                      69));
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
