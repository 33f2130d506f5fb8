#include "scenario_run.h"

#include <cstdio>
#include <cstdlib>

namespace incise::apps {

void failWith(const char* command, const std::string& message) {
  std::fprintf(stderr, "incise %s: %s\n", command, message.c_str());
  std::exit(2);
}

}  // namespace incise::apps
