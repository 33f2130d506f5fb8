// The `incise hid` subcommands (hid_command.cpp registers them) and the live half of `incise record`.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace incise::apps::hid {

// `incise hid` and its subcommands (list, decode, record, synth).
void addHidCommand(CLI::App& app);

struct HidDecodeArgs {
  std::string file;
  std::string scenario;  // its pen / 6-DOF mapping for the poses; empty: the defaults
  int device = 0;
  bool json = false;
};
int runHidDecode(const HidDecodeArgs& args);  // hid_decode.cpp

struct HidRecordArgs {
  std::string device;  // selector: VID:PID[:serial] or a /dev/hidraw path
  std::string out;
  std::string transport = "hidapi";
  std::string scenario;     // `incise record --device`: the mapping into tissue space
  double duration_s = 0.0;  // 0: until SIGINT / SIGTERM (or the device goes away, for hid record)
};
int runHidRecord(const HidRecordArgs& args);  // hid_record.cpp: raw reports to a hid-recorder file

struct HidCalibrateArgs {
  std::string device;  // selector: VID:PID[:serial] or a /dev/hidraw path
  std::string transport = "hidapi";
  std::string scenario;  // its pen block: the rectangle over the tissue and the keys not calibrated
  double timeout_s = 120.0;
};
int runHidCalibrate(const HidCalibrateArgs& args);  // hid_calibrate.cpp: a pen block from three presses
int runPoseRecord(const HidRecordArgs& args);       // hid_record.cpp: poses from a live device to a CSV trace

}  // namespace incise::apps::hid
