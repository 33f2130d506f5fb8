// Private to bspline/: the error helper its sources share (std::invalid_argument with the message) and
// the axes' names as messages quote them. Threads: any. Cost: O(1).
#pragma once

#include <stdexcept>
#include <string>

namespace incise::bspline::detail {

[[noreturn]] inline void fail(const std::string& message) { throw std::invalid_argument(message); }

inline constexpr const char* kAxisName[3] = {"u", "v", "w"};

}  // namespace incise::bspline::detail
