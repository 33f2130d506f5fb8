// The kill-safe half of the devices' recorders (TraceWriter, HidRecordingWriter): a file opened with
// open(2), records appended to a buffer in this process's memory and handed to the kernel with write(2),
// no stdio or iostream buffer in between, every flush_every records, on flush(), close() and in the
// destructor. What a call to one of these has handed over survives the process dying in any way (it is
// in the page cache); records still buffered are lost whole; a kill during a write(2) can leave at most
// one cut last line. The file appears at its path only with its header complete: the header is written to
// `path + ".tmp"`, which is then renamed onto the path (a previous file there stays whole until then; a
// kill before the rename leaves the .tmp, which the next recorder of the path truncates). The writers'
// headers (trace_csv.h, hid_recording.h) state the guarantee to users.
// Private to devices/ (held by pointer from the public writers, so their headers do not need this one).
//
// Threads: one thread at a time. Cost: O(1) amortised per record; one write(2) per flush.
// Failure: std::system_error naming `who` and the file ("<who>: cannot write 'path'") when the file cannot
// be created, written, fsync'ed or closed. A failed write keeps the unwritten bytes buffered for the next
// flush to retry (what was written is dropped from the buffer).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace incise::devices::detail {

class RecordStream {
 public:
  // Creates or truncates `path + ".tmp"` (mode 0644 before umask); writeHeader() renames it onto `path`. flush_every >= 1 (the writers check it);
  // reserve_bytes: the buffer's first allocation, roughly flush_every lines.
  RecordStream(std::filesystem::path path, std::string who, std::size_t flush_every, bool fsync_on_close,
               std::size_t reserve_bytes);
  // close() with errors swallowed.
  ~RecordStream();
  RecordStream(const RecordStream&) = delete;
  RecordStream& operator=(const RecordStream&) = delete;

  // Writes `text` (the file's header) now and renames the .tmp onto the path. On failure closes the file,
  // removes the .tmp and throws.
  void writeHeader(std::string_view text);
  // Append one record's text (lines ending in '\n') here, then call recordAdded().
  std::string& buffer() { return buffer_; }
  // Counts the record just appended; flushes when flush_every records are buffered.
  void recordAdded();
  // Hands the buffer to the kernel. No-op when closed or when nothing is buffered.
  void flush();
  // flush() then fsync(2). No-op when closed.
  void sync();
  // flush(), fsync(2) if fsync_on_close, close(2). Idempotent; the file is closed even when it throws.
  void close();

  bool isOpen() const { return fd_ >= 0; }
  std::size_t recordsWritten() const { return records_written_; }
  std::size_t recordsFlushed() const { return records_flushed_; }
  const std::filesystem::path& path() const { return path_; }
  const std::string& who() const { return who_; }

 private:
  void writeBuffer();
  [[noreturn]] void fail(int error, const char* what) const;

  std::filesystem::path path_, tmp_;
  std::string who_;
  std::size_t flush_every_;
  bool fsync_on_close_;
  int fd_ = -1;
  std::string buffer_;
  std::size_t records_written_ = 0;
  std::size_t records_flushed_ = 0;
  std::size_t records_buffered_ = 0;
};

}  // namespace incise::devices::detail
