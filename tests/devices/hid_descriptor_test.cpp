// The report-descriptor parser on the three real descriptors shipped in scenarios/hid/descriptors/ (fields
// checked by hand against their bytes) and on descriptors that must be refused.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "hid_fixture.h"
#include "incise/devices/hid_descriptor.h"
#include "incise/devices/hid_usages.h"

using namespace incise::devices;
using incise::test::loadShippedDescriptor;
using incise::test::parseBytes;

namespace {

const HidField& fieldWith(const HidReportLayout& layout, std::uint32_t usage) {
  for (const auto& f : layout.fields)
    for (std::uint32_t e = 0; e < f.count; ++e)
      if (f.usageOf(e) == usage) return f;
  FAIL("no field with usage " << hidUsageName(usage));
  throw;
}

// The bit offset of the element with `usage`.
std::uint32_t bitOf(const HidReportLayout& layout, std::uint32_t usage) {
  for (const auto& f : layout.fields)
    for (std::uint32_t e = 0; e < f.count; ++e)
      if (f.usageOf(e) == usage) return f.bit_offset + e * f.bit_size;
  FAIL("no field with usage " << hidUsageName(usage));
  throw;
}

std::string refusal(const std::vector<std::uint8_t>& bytes) {
  try {
    parseHidDescriptor(bytes);
  } catch (const HidDescriptorError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("hid_descriptor: XP-Pen Artist Pro 16 pen report, push/pop and all", "[devices][hid]") {
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor("xppen_artist_pro16_gen2_28bd_095b.txt"));
  REQUIRE(d.uses_report_ids);
  REQUIRE(d.applications() == std::vector<std::uint32_t>{hidUsage(0x0D, 0x02)});
  const HidReportLayout* pen = d.find(HidReportType::Input, 7);
  REQUIRE(pen != nullptr);
  CHECK(pen->bits == 72);
  CHECK(pen->wireBytes(true) == 10);
  // 09 42 09 44 09 45 09 3c 15 00 25 01 75 01 95 04 81 02: four 1-bit switches at bits 0..3.
  const HidField& tip = fieldWith(*pen, hidUsage(0x0D, 0x42));
  CHECK(tip.bit_offset == 0);
  CHECK(tip.count == 4);
  CHECK(tip.usages == std::vector<std::uint32_t>{hidUsage(0x0D, 0x42), hidUsage(0x0D, 0x44), hidUsage(0x0D, 0x45),
                                                 hidUsage(0x0D, 0x3C)});
  CHECK(bitOf(*pen, hidUsage(0x0D, 0x32)) == 5);
  // a4 05 01 09 30 65 13 55 0d 46 ff 34 26 ff 7f 81 02: X, 16 bits, 0..32767 -> 0..13567 mil (inch, 10^-3).
  const HidField& x = fieldWith(*pen, hidUsage(0x01, 0x30));
  CHECK(x.bit_offset == 8);
  CHECK(x.bit_size == 16);
  CHECK(x.logical_min == 0);
  CHECK(x.logical_max == 32767);
  CHECK(x.physical_max == 13567);
  CHECK(x.unit == 0x13);
  CHECK(x.unit_exponent == -3);
  CHECK(fieldWith(*pen, hidUsage(0x01, 0x31)).physical_max == 8480);
  // b4 (pop): back on the Digitizers page with no unit; 09 30 45 00 26 ff 3f 81 42: pressure 0..16383.
  const HidField& pressure = fieldWith(*pen, hidUsage(0x0D, 0x30));
  CHECK(pressure.bit_offset == 40);
  CHECK(pressure.logical_max == 16383);
  CHECK(pressure.physical_max == 16383);  // physical 0, 0: same as logical
  CHECK(pressure.unit == 0);
  CHECK(pressure.flags == 0x42);
  // 09 3d 15 81 25 7f 75 08: X tilt, signed 8 bits -127..127.
  const HidField& tilt = fieldWith(*pen, hidUsage(0x0D, 0x3D));
  CHECK(tilt.bit_offset == 56);
  CHECK(tilt.logical_min == -127);
  CHECK(tilt.isSigned());
}

TEST_CASE("hid_descriptor: Wacom PTH-660 pen report on the vendor page, 24-bit axes, twist", "[devices][hid]") {
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor("wacom_pth660_intuos_pro_m_056a_0357.txt"));
  REQUIRE(d.bytes.size() == 949);
  const HidReportLayout* pen = d.find(HidReportType::Input, 0x10);
  REQUIRE(pen != nullptr);
  CHECK(pen->wireBytes(true) == 27);
  // 0a 30 01 ... 47 80 57 00 00 15 00 27 00 af 00 00 75 18: 0xFF0D:0x0130 (Generic Desktop X), 24 bits.
  const HidField& x = fieldWith(*pen, hidUsage(0xFF0D, 0x0130));
  CHECK(hidEquivalentUsage(x.usages[0]) == hidUsage(0x01, 0x30));
  CHECK(x.bit_offset == 8);
  CHECK(x.bit_size == 24);
  CHECK(x.logical_max == 44800);
  CHECK(x.physical_max == 22400);
  CHECK(x.unit == 0x11);
  CHECK(x.unit_exponent == -3);
  CHECK(fieldWith(*pen, hidUsage(0xFF0D, 0x0131)).logical_max == 29600);
  const HidField& pressure = fieldWith(*pen, hidUsage(0xFF0D, 0x30));
  CHECK(pressure.bit_offset == 56);
  CHECK(pressure.logical_max == 8191);
  // 09 41 65 14 55 00 36 4c ff 46 b3 00 16 7c fc 26 83 03 75 10 95 01 81 0a: twist -900..899 -> -180..179 deg.
  const HidField& twist = fieldWith(*pen, hidUsage(0xFF0D, 0x41));
  CHECK(twist.logical_min == -900);
  CHECK(twist.logical_max == 899);
  CHECK(twist.physical_min == -180);
  CHECK(twist.physical_max == 179);
  CHECK(twist.unit == 0x14);
  CHECK(twist.flags == (hid_flags::kVariable | hid_flags::kWrap));
  // 17 00 00 00 80 27 ff ff ff 7f 75 20: a signed 4-byte minimum.
  const HidField& serial = fieldWith(*pen, hidUsage(0xFF0D, 0x5B));
  CHECK(serial.logical_min == -2147483648LL);
  CHECK(serial.logical_max == 2147483647LL);
  CHECK(serial.bit_size == 32);
  // The mouse, the pad and the feature reports are there too.
  CHECK(d.find(HidReportType::Input, 0x01) != nullptr);
  CHECK(d.find(HidReportType::Input, 0x11) != nullptr);
  CHECK(d.find(HidReportType::Feature, 0x02) != nullptr);
  REQUIRE(d.find(HidReportType::Feature, 0xd9) != nullptr);
  CHECK(d.find(HidReportType::Feature, 0xd9)->bits == 2560 * 8);  // 96 00 0a: a 2-byte report count
}

TEST_CASE("hid_descriptor: SpaceNavigator's three input reports and its relative axes", "[devices][hid]") {
  const HidDescriptor d = parseHidDescriptor(loadShippedDescriptor("3dconnexion_spacenavigator_046d_c626.txt"));
  REQUIRE(d.bytes.size() == 228);
  CHECK(d.applications().front() == hidUsage(0x01, 0x08));  // Multi-axis Controller
  const HidReportLayout* translation = d.find(HidReportType::Input, 1);
  const HidReportLayout* rotation = d.find(HidReportType::Input, 2);
  const HidReportLayout* buttons = d.find(HidReportType::Input, 3);
  REQUIRE(translation != nullptr);
  REQUIRE(rotation != nullptr);
  REQUIRE(buttons != nullptr);
  const HidField& xyz = fieldWith(*translation, hidUsage(0x01, 0x30));
  CHECK(xyz.count == 3);
  CHECK(xyz.usages[2] == hidUsage(0x01, 0x32));
  CHECK(xyz.logical_min == -350);  // 16 a2 fe
  CHECK(xyz.logical_max == 350);
  CHECK(xyz.physical_min == -1400);  // 36 88 fa
  CHECK(xyz.unit_exponent == -4);    // 55 0c
  CHECK(xyz.isRelative());           // 81 06: what the firmware declares (the quirk)
  CHECK(bitOf(*rotation, hidUsage(0x01, 0x35)) == 32);
  // 05 01 05 09 19 01 29 02: the second page item wins.
  CHECK(bitOf(*buttons, hidUsage(0x09, 2)) == 1);
  CHECK(buttons->bits == 16);
  CHECK(d.find(HidReportType::Output, 4) != nullptr);  // the LED
  CHECK(d.find(HidReportType::Feature, 0x19) != nullptr);
}

TEST_CASE("hid_descriptor: signed and unsigned ranges, 4-byte usages, delimiters, long items", "[devices][hid]") {
  // Usage Page GD, Usage X, Logical Min -1 (1 byte), Logical Max 0xff (2 bytes: 255), 8 bits, Input.
  const HidDescriptor a =
      parseBytes({0x05, 0x01, 0x09, 0x30, 0x15, 0x00, 0x26, 0xff, 0x00, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02});
  CHECK(a.reports.at(0).fields.at(0).logical_max == 255);
  CHECK_FALSE(a.reports.at(0).fields.at(0).isSigned());
  // A negative minimum makes the maximum signed: 25 ff after 15 80 is -1.
  const HidDescriptor b =
      parseBytes({0x05, 0x01, 0x09, 0x30, 0x15, 0x80, 0x25, 0xff, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02});
  CHECK(b.reports.at(0).fields.at(0).logical_min == -128);
  CHECK(b.reports.at(0).fields.at(0).logical_max == -1);
  // A 4-byte usage carries its page (Digitizers tip pressure) whatever the current page; unit exponent 0xfd.
  const HidDescriptor c = parseBytes({0x05, 0x01, 0x0b, 0x30, 0x00, 0x0d, 0x00, 0x55, 0xfd, 0x15, 0x00, 0x25, 0x01,
                                      0x75, 0x01, 0x95, 0x01, 0x81, 0x02});
  CHECK(c.reports.at(0).fields.at(0).usages.at(0) == hidUsage(0x0D, 0x30));
  CHECK(c.reports.at(0).fields.at(0).unit_exponent == -3);
  // Delimiter: only the first usage of the set is kept; a long item is skipped.
  const HidDescriptor e = parseBytes({0x05, 0x01, 0xa9, 0x01, 0x09, 0x30, 0x09, 0x31, 0xa9, 0x00, 0xfe, 0x02, 0x10,
                                      0xaa, 0xbb, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x01, 0x81, 0x02});
  CHECK(e.reports.at(0).fields.at(0).usages == std::vector<std::uint32_t>{hidUsage(0x01, 0x30)});
  // Array field: Usage Min/Max 1..3 on the Button page, indices 1..3.
  const HidDescriptor f =
      parseBytes({0x05, 0x09, 0x19, 0x01, 0x29, 0x03, 0x15, 0x01, 0x25, 0x03, 0x75, 0x02, 0x95, 0x01, 0x81, 0x00});
  CHECK_FALSE(f.reports.at(0).fields.at(0).isVariable());
  CHECK(f.reports.at(0).fields.at(0).usages.size() == 3);
}

TEST_CASE("hid_descriptor: broken descriptors are refused with the byte offset", "[devices][hid]") {
  const std::vector<std::uint8_t> good_tail = {0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x08, 0x81, 0x02};
  CHECK(refusal({}) == "report descriptor: empty");
  // Truncated: Logical Maximum announces 2 bytes, one is there.
  CHECK(refusal({0x05, 0x01, 0x26, 0xff}) ==
        "report descriptor byte 2 (item 0x26): truncated: the item needs 2 data bytes, 1 left");
  // Unbalanced collections.
  auto open = std::vector<std::uint8_t>{0x05, 0x01, 0x09, 0x02, 0xa1, 0x01};
  open.insert(open.end(), good_tail.begin(), good_tail.end());
  CHECK(refusal(open).find("collection opened at byte 4 is never closed") != std::string::npos);
  auto extra_end = good_tail;
  extra_end.push_back(0xc0);
  CHECK(refusal(extra_end) == "report descriptor byte 10 (item 0xc0): End Collection without an open collection");
  CHECK(refusal({0xb4}) == "report descriptor byte 0 (item 0xb4): Pop without a Push");
  CHECK(refusal({0x76, 0x01, 0x01}) == "report descriptor byte 0 (item 0x76): Report Size 257 bits: must be 1..256");
  CHECK(refusal({0x85, 0x00}) == "report descriptor byte 0 (item 0x85): Report ID 0: must be 1..255");
  // Unknown items: main tag 0xD, global tag 0xC, local tag 0xB, reserved type 3 (0x0c = tag 0, type 3).
  CHECK(refusal({0xd1, 0x00}).find("unknown main item tag 0x0d") != std::string::npos);
  CHECK(refusal({0xc5, 0x00}).find("unknown global item tag 0x0c") != std::string::npos);
  CHECK(refusal({0xb9, 0x00}).find("unknown local item tag 0x0b") != std::string::npos);
  CHECK(refusal({0x0d, 0x00}).find("reserved item type 3") != std::string::npos);
  CHECK(refusal({0x81, 0x02}).find("Input item before any Report Size and Report Count") != std::string::npos);
  // IDs for some reports and not for others.
  auto mixed = good_tail;
  mixed.insert(mixed.end(), {0x85, 0x02});
  CHECK(refusal(mixed).find("Report ID after fields without one") != std::string::npos);
  // A report over 4096 bytes.
  CHECK(refusal({0x75, 0x08, 0x96, 0x01, 0x10, 0x81, 0x02}).find("grows over 4096 bytes") != std::string::npos);
  // A 4-byte Report Count of 2^31 - 1: refused before anything is allocated for it (found by fuzzing).
  CHECK(refusal({0x09, 0x30, 0x75, 0x08, 0x97, 0xff, 0xff, 0xff, 0x7f, 0x81, 0x02}).find("grows over 4096 bytes") !=
        std::string::npos);
  // A push stack that never ends.
  CHECK(refusal(std::vector<std::uint8_t>(17, 0xa4)).find("Push nested over 16 deep") != std::string::npos);
  CHECK(refusal({0x05, 0x01}) == "report descriptor: declares no report fields");
}

TEST_CASE("hid_descriptor: hex files read with their line numbers", "[devices][hid]") {
  CHECK(parseHexBytes("# comment\n05 01  09\t08\n# more\n") == std::vector<std::uint8_t>{0x05, 0x01, 0x09, 0x08});
  CHECK_THROWS_WITH(parseHexBytes("05 01\n09 0x8\n"), "line 2: '0x8' is not a two-digit hex byte");
  CHECK_THROWS_WITH(parseHexBytes("05 1\n"), "line 1: '1' is not a two-digit hex byte");
  CHECK_THROWS_WITH(parseHexBytes("05 zz\n"), "line 1: 'zz' is not a two-digit hex byte");
}

TEST_CASE("hid_usages: names as the HID Usage Tables spell them", "[devices][hid]") {
  CHECK(hidUsageName(hidUsage(0x01, 0x30)) == "X");
  CHECK(hidUsageName(hidUsage(0x01, 0x35)) == "Rz");
  CHECK(hidUsageName(hidUsage(0x0D, 0x30)) == "Tip Pressure");
  CHECK(hidUsageName(hidUsage(0x0D, 0x3D)) == "X Tilt");
  CHECK(hidUsageName(hidUsage(0x09, 3)) == "Button 3");
  CHECK(hidUsageName(hidUsage(0xFF0D, 0x0130)) == "X");  // Wacom's vendor page through its equivalence
  CHECK(hidUsageName(hidUsage(0xFF0D, 0x0042)) == "Tip Switch");
  CHECK(hidUsageName(hidUsage(0xFF00, 0x0001)) == "Vendor 0xff00:0x0001");
  CHECK(hidUsagePageName(0x0D) == "Digitizers");
  CHECK(hidUsagePageName(0xFF0D) == "Vendor Defined 0xff0d");
}
