// The extractor and its inverse: hand-made reports decoded to the values their bits hold, and every input
// field of the three shipped descriptors round-tripped through encoder and decoder bit for bit.
#include <catch2/catch.hpp>

#include <random>
#include <vector>

#include "hid_fixture.h"
#include "incise/devices/hid_report.h"
#include "incise/devices/hid_usages.h"

using namespace incise::devices;
using namespace incise::test;

namespace {

const HidValue* valueOf(const std::vector<HidValue>& values, std::size_t count, std::uint32_t usage) {
  for (std::size_t i = 0; i < count; ++i)
    if (values[i].usage == usage) return &values[i];
  return nullptr;
}

}  // namespace

TEST_CASE("hid_report: an XP-Pen report decoded by hand", "[devices][hid]") {
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor(kXpPenDescriptor));
  const HidReportDecoder decoder(d);
  // ID 7; tip + in range (bits 0, 5); X 0x4000; Y 0x1000; pressure 0x2000; X tilt -20; Y tilt 30.
  const std::vector<std::uint8_t> raw = {0x07, 0x21, 0x00, 0x40, 0x00, 0x10, 0x00, 0x20, 0xec, 0x1e};
  std::vector<HidValue> values(decoder.maxValues());
  const HidDecoded decoded = decoder.decode(raw, values);
  REQUIRE(decoded.status == HidDecodeStatus::Ok);
  CHECK(decoded.layout->id == 7);
  CHECK(valueOf(values, decoded.values, hidUsage(0x0D, 0x42))->logical == 1);
  CHECK(valueOf(values, decoded.values, hidUsage(0x0D, 0x44))->logical == 0);
  CHECK(valueOf(values, decoded.values, hidUsage(0x0D, 0x32))->logical == 1);
  const HidValue* x = valueOf(values, decoded.values, hidUsage(0x01, 0x30));
  CHECK(x->logical == 0x4000);
  CHECK(x->physical == Approx(13567.0 * 0x4000 / 32767 * 1e-3));  // inches
  CHECK(hidUnitName(d.reports[0].fields[x->field].unit) == "in");
  CHECK(valueOf(values, decoded.values, hidUsage(0x0D, 0x30))->logical == 0x2000);
  CHECK(valueOf(values, decoded.values, hidUsage(0x0D, 0x3D))->logical == -20);
  CHECK(valueOf(values, decoded.values, hidUsage(0x0D, 0x3E))->logical == 30);
}

TEST_CASE("hid_report: bad reports are reported, never read past their end", "[devices][hid]") {
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor(kXpPenDescriptor));
  const HidReportDecoder decoder(d);
  std::vector<HidValue> values(decoder.maxValues());
  CHECK(decoder.decode({}, values).status == HidDecodeStatus::Empty);
  const std::vector<std::uint8_t> unknown = {0x09, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  CHECK(decoder.decode(unknown, values).status == HidDecodeStatus::UnknownReportId);
  const std::vector<std::uint8_t> short_report = {0x07, 0x21, 0x00, 0x40};
  const HidDecoded decoded = decoder.decode(short_report, values);
  CHECK(decoded.status == HidDecodeStatus::TooShort);
  CHECK(decoded.values == 0);
}

TEST_CASE("hid_report: a 64-bit field reads as its low 32 bits, as hid-core reads it", "[devices][hid]") {
  // Pen: Transducer Serial Number, 64 bits, signed 32-bit range; then Tip Switch and 7 bits of padding (the
  // USI pens of the Elan and Goodix screens send their serial so).
  const HidDescriptor d = parseBytes({0x05, 0x0d, 0x09, 0x02, 0xa1, 0x01, 0x09, 0x5b, 0x17, 0x00, 0x00, 0x00, 0x80,
                                      0x27, 0xff, 0xff, 0xff, 0x7f, 0x75, 0x40, 0x95, 0x01, 0x81, 0x02, 0x09, 0x42,
                                      0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x81, 0x02, 0x75, 0x07, 0x81, 0x03, 0xc0});
  const HidField& serial = d.reports[0].fields[0];
  const HidField& tip = d.reports[0].fields[1];
  CHECK(serial.bit_size == 64);
  CHECK(tip.bit_offset == 64);
  std::vector<std::uint8_t> raw = {0x78, 0x56, 0x34, 0x12, 0xab, 0xcd, 0xef, 0x01, 0x01};
  CHECK(readHidElement(raw, serial, 0) == 0x12345678);
  CHECK(readHidElement(raw, tip, 0) == 1);
  raw = {0xfe, 0xff, 0xff, 0xff, 0, 0, 0, 0, 0};
  CHECK(readHidElement(raw, serial, 0) == -2);  // signed: the low 32 bits sign-extended
  writeHidElement(raw, serial, 0, -3);          // two's complement over all 64 bits
  CHECK(raw == std::vector<std::uint8_t>{0xfd, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0});
  writeHidElement(raw, serial, 0, 7);
  CHECK(raw == std::vector<std::uint8_t>{7, 0, 0, 0, 0, 0, 0, 0, 0});
}

TEST_CASE("hid_report: units, physical values and their inverse", "[devices][hid]") {
  CHECK(hidUnitName(0x11) == "cm");
  CHECK(hidUnitName(0x14) == "deg");
  CHECK(hidUnitName(0x12) == "rad");
  CHECK(hidUnitName(0xF011) == "cm/s");
  CHECK(hidUnitName(0) == "");
  CHECK(hidUnitToSi(0x11) == 0.01);
  CHECK(hidUnitToSi(0x13) == 0.0254);
  CHECK(hidUnitToSi(0xF011) == 0.0);
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor(kWacomDescriptor));
  const HidReportLayout& pen = *d.find(HidReportType::Input, 0x10);
  for (const HidField& f : pen.fields) {
    if (f.isConstant()) continue;
    for (const std::int64_t logical : {f.logical_min, f.logical_max, (f.logical_min + f.logical_max) / 2})
      CHECK(hidLogical(f, hidPhysical(f, logical)) == logical);
  }
}

TEST_CASE("hid_report: every input field of the shipped descriptors round-trips bit for bit", "[devices][hid]") {
  std::mt19937_64 random(7);
  for (const char* name : {kWacomDescriptor, kXpPenDescriptor, kSpaceNavigatorDescriptor}) {
    INFO(name);
    const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor(name));
    const HidReportDecoder decoder(d);
    const HidReportEncoder encoder(d);
    std::vector<HidValue> values(decoder.maxValues());
    for (const HidReportLayout& layout : d.reports) {
      if (layout.type != HidReportType::Input) continue;
      for (int trial = 0; trial < 50; ++trial) {
        // Random data bits, constant bits zero: decode, re-encode every value, get the same bytes.
        std::vector<std::uint8_t> raw = encoder.blank(layout);
        const std::size_t start = d.uses_report_ids ? 1 : 0;
        std::vector<std::uint8_t> payload(raw.begin() + static_cast<long>(start), raw.end());
        for (const HidField& f : layout.fields)
          if (!f.isConstant())
            for (std::uint32_t e = 0; e < f.count; ++e)
              writeHidElement(payload, f, e, static_cast<std::int64_t>(random()));
        std::copy(payload.begin(), payload.end(), raw.begin() + static_cast<long>(start));
        const HidDecoded decoded = decoder.decode(raw, values);
        REQUIRE(decoded.status == HidDecodeStatus::Ok);
        std::vector<std::uint8_t> again = encoder.blank(layout);
        std::vector<std::uint8_t> again_payload(again.begin() + static_cast<long>(start), again.end());
        for (std::size_t i = 0; i < decoded.values; ++i) {
          const HidField& f = layout.fields[values[i].field];
          writeHidElement(again_payload, f, values[i].element, values[i].logical);
        }
        std::copy(again_payload.begin(), again_payload.end(), again.begin() + static_cast<long>(start));
        REQUIRE(again == raw);
      }
    }
  }
}

TEST_CASE("hid_report: the encoder sets values by usage, the decoder reads them back", "[devices][hid]") {
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor(kSpaceNavigatorDescriptor));
  const HidReportEncoder encoder(d);
  const HidReportDecoder decoder(d);
  const HidReportLayout& rotation = *d.find(HidReportType::Input, 2);
  std::vector<std::uint8_t> raw = encoder.blank(rotation);
  REQUIRE(raw.size() == 7);
  CHECK(encoder.setLogical(raw, rotation, hidUsage(0x01, 0x34), -350));
  CHECK(encoder.setLogical(raw, rotation, hidUsage(0x01, 0x35), 123));
  CHECK_FALSE(encoder.setLogical(raw, rotation, hidUsage(0x01, 0x30), 1));  // X is in report 1
  CHECK(raw == std::vector<std::uint8_t>{0x02, 0x00, 0x00, 0xa2, 0xfe, 0x7b, 0x00});
  std::vector<HidValue> values(decoder.maxValues());
  const HidDecoded decoded = decoder.decode(raw, values);
  REQUIRE(decoded.values == 3);
  CHECK(values[1].logical == -350);
  CHECK(values[1].physical == Approx(-0.14));  // -1400 * 10^-4 cm
  CHECK(values[2].logical == 123);
}
