// libFuzzer harness: the CSV trace reader (devices/trace_csv.h). The input is a trace file's bytes; the
// reader reads every sample, and after a TraceError goes on at the following line (as the header says it
// stands there), so one input exercises the recovery too. TraceError is the documented failure; anything
// else escaping, a crash, a hang or a sanitizer report is a finding.
// scripts/fuzz.sh runs it with -max_len=1024: the reader's grammar is per line, and what it carries from one
// line to the next (the header, the comment block after it, the previous sample's time for the strictly
// increasing check, the unterminated tail) needs only a few lines; 1 KB holds the header and five samples
// at full precision, dozens of short ones. At the default 4 KB a fuzzed trace is mostly bad lines, each a
// TraceError, and under ASan the unwinding and the allocator held the harness to 700-3,000 exec/s
// (docs/reliability.md, "Fuzzing"); the loop below, recovery at the next line included, is unchanged.
#include <cstddef>
#include <cstdint>

#include "fuzz_input.h"
#include "incise/devices/trace_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = incise::fuzz::writeInput(data, size, "trace.csv");
  try {
    incise::devices::TraceReader reader(path);
    // Each next() consumes a line, so at most size + 1 calls; the bound turns a reader stuck on one line
    // into a clean exit here and a failed check below, not a timeout.
    std::size_t calls = 0;
    for (; calls <= size + 1; ++calls) {
      try {
        if (!reader.next()) break;
      } catch (const incise::devices::TraceError&) {
      }
    }
    if (calls > size + 1) __builtin_trap();
    (void)reader.describe();
  } catch (const incise::devices::TraceError&) {
  }
  return 0;
}
