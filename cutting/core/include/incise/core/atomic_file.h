// The one way incise writes a whole output file (meshes, tet meshes, JSON reports, JSON lines): the text
// goes to `path + ".tmp"` through a 1 MiB buffer and is renamed onto `path` by commit(), so a crash, a
// kill or a full disk leaves either no file, the previous complete file, or the new complete file —
// never a torn one. A writer destroyed before commit() removes its .tmp; a SIGKILL (no destructor runs)
// leaves it: `path + ".tmp"` is never read as the output, and the next writer of the path truncates it
// (tests/apps/kill_test.sh kills replay, wrap, cut and record at seeded moments and checks all this).
//
// Numbers: operator<<(double) writes the shortest text that reads back to the same double (std::to_chars,
// locale-independent, round trip); number17(double) the fixed 17-significant-digit form the mesh files use.
// Threads: one writer per thread; distinct paths may be written concurrently. Cost: O(bytes); allocates
// (not for the sim thread). Failure: FileError (a std::runtime_error naming the file and the errno text)
// when the .tmp cannot be created, written, closed or renamed; the .tmp is removed then.
// Streams (a trace recorded as it goes) are not whole files: devices' TraceWriter flushes them itself.
#pragma once

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace incise::core {

struct FileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  AtomicFile& operator<<(std::string_view text);
  AtomicFile& operator<<(const char* text) { return *this << std::string_view(text); }
  AtomicFile& operator<<(char c) { return *this << std::string_view(&c, 1); }
  AtomicFile& operator<<(double x);  // shortest round trip
  AtomicFile& operator<<(long long x);
  AtomicFile& operator<<(int x) { return *this << static_cast<long long>(x); }
  AtomicFile& operator<<(std::size_t x) { return *this << static_cast<long long>(x); }
  // 17 significant digits, "general" format (what OBJ/PLY/VTU output has always used).
  AtomicFile& number17(double x);

  // Flushes and closes the .tmp; throws FileError on failure. commit() calls it if it was not called.
  void close();
  // close(), then renames the .tmp onto the path. After it the writer does nothing more.
  void commit();

  const std::filesystem::path& path() const noexcept { return path_; }

 private:
  void flush();
  [[noreturn]] void fail(const std::string& what);

  std::filesystem::path path_, tmp_;
  std::FILE* file_ = nullptr;
  std::string buffer_;
  bool committed_ = false;
};

// Writes `contents` to `path` atomically (AtomicFile, then commit()).
void writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

// Runs `write()` (which writes and commits AtomicFiles) and rethrows a FileError as an `Error` with the same
// message, for the save functions whose contract names their own error type (MeshError for meshes).
template <typename Error, typename Write>
void rethrowFileErrorAs(Write&& write) {
  try {
    std::forward<Write>(write)();
  } catch (const FileError& e) {
    throw Error(e.what());
  }
}

}  // namespace incise::core
