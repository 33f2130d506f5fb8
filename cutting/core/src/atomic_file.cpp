#include "incise/core/atomic_file.h"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <system_error>
#include <utility>

namespace incise::core {

namespace {
constexpr std::size_t kChunk = std::size_t{1} << 20;
}

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)), tmp_(path_.string() + ".tmp") {
  file_ = std::fopen(tmp_.c_str(), "wb");
  if (!file_) throw FileError("cannot write " + tmp_.string() + ": " + std::strerror(errno));
  buffer_.reserve(kChunk + 256);
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_) {
    std::error_code ignored;
    std::filesystem::remove(tmp_, ignored);
  }
}

AtomicFile& AtomicFile::operator<<(std::string_view text) {
  buffer_ += text;
  if (buffer_.size() >= kChunk) flush();
  return *this;
}

AtomicFile& AtomicFile::operator<<(double x) {
  char s[64];
  const auto r = std::to_chars(s, s + sizeof s, x);
  return *this << std::string_view(s, static_cast<std::size_t>(r.ptr - s));
}

AtomicFile& AtomicFile::operator<<(long long x) {
  char s[32];
  const auto r = std::to_chars(s, s + sizeof s, x);
  return *this << std::string_view(s, static_cast<std::size_t>(r.ptr - s));
}

AtomicFile& AtomicFile::number17(double x) {
  char s[64];
  const auto r = std::to_chars(s, s + sizeof s, x, std::chars_format::general, 17);
  return *this << std::string_view(s, static_cast<std::size_t>(r.ptr - s));
}

void AtomicFile::flush() {
  if (!file_) fail("already closed");
  if (!buffer_.empty() && std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
    fail(std::strerror(errno));
  buffer_.clear();
}

void AtomicFile::fail(const std::string& what) {
  if (file_) std::fclose(std::exchange(file_, nullptr));
  throw FileError("cannot write " + tmp_.string() + ": " + what);
}

void AtomicFile::close() {
  if (!file_) return;
  flush();
  if (std::fclose(std::exchange(file_, nullptr)) != 0) fail(std::strerror(errno));
}

void AtomicFile::commit() {
  if (committed_) return;
  close();
  std::error_code error;
  std::filesystem::rename(tmp_, path_, error);
  if (error) throw FileError("cannot rename " + tmp_.string() + " to " + path_.string() + ": " + error.message());
  committed_ = true;
}

void writeFileAtomically(const std::filesystem::path& path, std::string_view contents) {
  AtomicFile out(path);
  out << contents;
  out.commit();
}

}  // namespace incise::core
