#include "record_stream.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <system_error>
#include <utility>

namespace incise::devices::detail {

RecordStream::RecordStream(std::filesystem::path path, std::string who, std::size_t flush_every, bool fsync_on_close,
                           std::size_t reserve_bytes)
    : path_(std::move(path)), who_(std::move(who)), flush_every_(flush_every), fsync_on_close_(fsync_on_close) {
  tmp_ = path_;
  tmp_ += ".tmp";
  fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) fail(errno, "create");
  buffer_.reserve(reserve_bytes);
}

RecordStream::~RecordStream() {
  try {
    close();
  } catch (...) {
    // A destructor cannot report; the writers' close() is there for callers who want to know.
  }
}

void RecordStream::fail(int error, const char* what) const {
  throw std::system_error(error, std::generic_category(), who_ + ": cannot " + what + " '" + path_.string() + "'");
}

void RecordStream::writeHeader(std::string_view text) {
  buffer_.append(text);
  try {
    writeBuffer();
    if (::rename(tmp_.c_str(), path_.c_str()) != 0) fail(errno, "rename onto");
  } catch (...) {
    ::close(std::exchange(fd_, -1));
    ::unlink(tmp_.c_str());
    throw;
  }
}

void RecordStream::recordAdded() {
  ++records_written_;
  ++records_buffered_;
  if (records_buffered_ >= flush_every_) flush();
}

void RecordStream::flush() {
  if (fd_ < 0) return;
  writeBuffer();
}

void RecordStream::writeBuffer() {
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      buffer_.erase(0, done);
      fail(error, "write");
    }
    done += static_cast<std::size_t>(n);
  }
  buffer_.clear();
  records_flushed_ = records_written_;
  records_buffered_ = 0;
}

void RecordStream::sync() {
  if (fd_ < 0) return;
  writeBuffer();
  if (::fsync(fd_) != 0) fail(errno, "fsync");
}

void RecordStream::close() {
  if (fd_ < 0) return;
  try {
    if (fsync_on_close_)
      sync();
    else
      writeBuffer();
  } catch (...) {
    ::close(std::exchange(fd_, -1));
    throw;
  }
  if (::close(std::exchange(fd_, -1)) != 0) fail(errno, "close");
}

}  // namespace incise::devices::detail
