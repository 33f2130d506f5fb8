// The error every scenario loader throws (replay and wrap scenarios): a std::runtime_error whose message
// says where — "file:line:column: ..." for JSON syntax, "file: key.path: ..." for a missing, mistyped or
// out-of-range value or a missing file.
#pragma once

#include <stdexcept>

namespace incise::sim {

struct ScenarioError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace incise::sim
