// Tests for cutting/core/src/atomic_file.cpp: a committed writer leaves the whole text at the path and no .tmp,
// an uncommitted one leaves no file or the previous file intact, failures are FileErrors naming the file,
// and the two number formats (shortest round trip, 17 significant digits).
#include "incise/core/atomic_file.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

#include "support/temp_dir.h"

namespace incise::core {
namespace {

namespace fs = std::filesystem;
using incise::test::readFile;
using incise::test::TempDir;

long entries(const fs::path& dir) {
  return static_cast<long>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// The text `write(AtomicFile&)` produces, through a committed writer.
template <typename Write>
std::string written(const TempDir& dir, Write write) {
  const fs::path path = dir.path() / "numbers.txt";
  AtomicFile out(path);
  write(out);
  out.commit();
  return readFile(path);
}

}  // namespace

TEST_CASE("atomic_file: a committed writer leaves the whole text at the path and no .tmp", "[cutting]") {
  TempDir dir;
  const fs::path path = dir.path() / "out.txt";
  {
    AtomicFile out(path);
    REQUIRE(out.path() == path);
    out << "a line\n" << 'x' << std::string_view(" and ") << 42 << ' ' << std::size_t{7} << '\n';
    REQUIRE_FALSE(fs::exists(path));  // nothing at the path before commit()
    REQUIRE(fs::exists(path.string() + ".tmp"));
    out.commit();
    out.commit();  // a second commit() does nothing
  }
  REQUIRE(readFile(path) == "a line\nx and 42 7\n");
  REQUIRE(entries(dir.path()) == 1);

  // More than the 1 MiB buffer: flushed on the way, the bytes unchanged.
  std::string big;
  for (int i = 0; big.size() < 3'000'000; ++i) big += std::to_string(i) + (i % 17 == 0 ? "\n" : " ");
  writeFileAtomically(path, big);
  REQUIRE(readFile(path) == big);
  REQUIRE(entries(dir.path()) == 1);
}

TEST_CASE("atomic_file: a writer destroyed without commit leaves no file, or the previous file intact", "[cutting]") {
  TempDir dir;
  const fs::path path = dir.path() / "out.txt";
  {
    AtomicFile out(path);
    out << "never committed\n";
  }
  REQUIRE_FALSE(fs::exists(path));
  REQUIRE(entries(dir.path()) == 0);

  writeFileAtomically(path, "the previous file\n");
  {
    AtomicFile out(path);
    std::string big(2'000'000, 'z');  // flushed to the .tmp, still not committed
    out << big;
    out.close();
  }
  REQUIRE(readFile(path) == "the previous file\n");
  REQUIRE(entries(dir.path()) == 1);
}

TEST_CASE("atomic_file: a path in a missing folder throws FileError naming the path", "[cutting]") {
  TempDir dir;
  const fs::path nowhere = dir.path() / "no-such-folder" / "out.txt";
  try {
    AtomicFile out(nowhere);
    FAIL("opening " << nowhere << " did not throw");
  } catch (const FileError& e) {
    REQUIRE_THAT(e.what(), Catch::Contains(nowhere.string()));
  }
  REQUIRE_THROWS_AS(writeFileAtomically(nowhere, "text"), FileError);
  REQUIRE_FALSE(fs::exists(nowhere.parent_path()));

  // The target is a non-empty folder: the .tmp is written, the rename fails, the .tmp goes away.
  const fs::path blocked = dir.path() / "blocked.txt";
  fs::create_directories(blocked / "inside");
  try {
    writeFileAtomically(blocked, "text");
    FAIL("renaming onto the folder " << blocked << " did not throw");
  } catch (const FileError& e) {
    REQUIRE_THAT(e.what(), Catch::Contains(blocked.string()));
  }
  REQUIRE_FALSE(fs::exists(blocked.string() + ".tmp"));
  REQUIRE(entries(dir.path()) == 1);
}

TEST_CASE("atomic_file: << writes the shortest round trip, number17 17 significant digits", "[cutting]") {
  TempDir dir;
  REQUIRE(written(dir, [](AtomicFile& out) { out << 0.1; }) == "0.1");
  REQUIRE(written(dir, [](AtomicFile& out) { out.number17(0.1); }) == "0.10000000000000001");
  REQUIRE(written(dir, [](AtomicFile& out) { out << 1.0 << ' ' << -2.5 << ' ' << 1e-300; }) == "1 -2.5 1e-300");
  REQUIRE(written(dir, [](AtomicFile& out) {
            out.number17(1.0) << ' ';
            out.number17(-2.5);
          }) == "1 -2.5");
  REQUIRE(written(dir, [](AtomicFile& out) { out.number17(1.0 / 3.0); }) == "0.33333333333333331");
  REQUIRE(written(dir, [](AtomicFile& out) { out << -12 << ' ' << 9'000'000'000LL; }) == "-12 9000000000");
}

}  // namespace incise::core
