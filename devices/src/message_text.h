// Numbers and fields as the devices' error messages quote them. Private to devices/ (which does not
// depend on cutting's formatter). Threads: any. Cost: O(1); allocates the string.
#pragma once

#include <charconv>
#include <cstddef>
#include <string>
#include <string_view>

namespace incise::devices::detail {

// Shortest text that reads back to the same double (std::to_chars, locale-independent).
inline std::string shortest(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

// A field as quoted in a message, cut at 40 characters: garbage after a crash can be long.
inline std::string quoteField(std::string_view field) {
  constexpr std::size_t kMax = 40;
  // Built by append: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string&& here.
  std::string text = "'";
  text.append(field.substr(0, kMax)).append(field.size() > kMax ? "...'" : "'");
  return text;
}

}  // namespace incise::devices::detail
