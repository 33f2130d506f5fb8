// Private: numbers in error messages, exactly (17 significant digits, so the value in a message is the
// value that was refused) and locale-independently.
#pragma once

#include <sstream>
#include <string>

#include <Eigen/Core>

namespace incise::cutting::detail {

inline std::string str(double x) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.precision(17);
  s << x;
  return s.str();
}

// Streamed, not concatenated: GCC 12 warns falsely (-Wrestrict, PR 105651) on "(" + std::string.
inline std::string str(const Eigen::Vector3d& p) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.precision(17);
  s << '(' << p[0] << ", " << p[1] << ", " << p[2] << ')';
  return s.str();
}

}  // namespace incise::cutting::detail
