// Framing of a ULog file into messages (spec: docs.px4.io/main/en/dev_log/ulog_file_format.html):
// the 16-byte header (magic "ULog" 0x01 0x12 0x35, version byte, uint64 timestamp in us), then
// messages of a 3-byte header (uint16 msg_size, uint8 msg_type) and msg_size payload bytes. The
// file is read through a fixed buffer, so memory does not depend on the file's size.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace mavloc::ulog {

constexpr int kHeaderBytes = 16;
constexpr int kMessageHeaderBytes = 3;
// The sync message's payload (ulog_file_format.html, "Synchronization message").
constexpr uint8_t kSyncMagic[8] = {0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12};

struct RawMessage {
  char type = 0;
  uint64_t offset = 0;            // of the message header in the file
  const uint8_t* data = nullptr;  // payload, valid until the next call on the stream
  int size = 0;
};

class MessageStream {
 public:
  // Opens `path` and reads the header. Throws InputError (not ULog, too short, unreadable).
  explicit MessageStream(const std::string& path);
  ~MessageStream();
  MessageStream(const MessageStream&) = delete;
  MessageStream& operator=(const MessageStream&) = delete;

  int version() const { return version_; }
  uint64_t header_timestamp_us() const { return header_timestamp_us_; }
  uint64_t file_bytes() const { return file_bytes_; }
  // File offset of the next message header.
  uint64_t offset() const { return buffer_offset_ + begin_; }

  // The next complete message. Returns false at the end of the file, or when the next message
  // would end after the read limit. After false, partial() tells whether the file ended inside a
  // message (then partial_offset() is that message's offset).
  bool Next(RawMessage* message);
  bool partial() const { return partial_; }
  uint64_t partial_offset() const { return partial_offset_; }
  int partial_declared_size() const { return partial_declared_size_; }

  // Messages ending after `end_offset` are not returned (UINT64_MAX: no limit).
  void SetReadLimit(uint64_t end_offset) { limit_ = end_offset; }
  void Seek(uint64_t offset);
  // Moves to just after the next sync sequence at or after `from`; false when there is none.
  bool SeekPastSync(uint64_t from);

 private:
  // Makes at least `n` bytes available from begin_ if the file has them; returns the number
  // available (possibly fewer at the end of the file).
  size_t Ensure(size_t n);

  std::string path_;
  std::FILE* file_ = nullptr;
  uint64_t file_bytes_ = 0;
  int version_ = 0;
  uint64_t header_timestamp_us_ = 0;
  std::vector<uint8_t> buffer_;
  uint64_t buffer_offset_ = 0;  // file offset of buffer_[0]
  size_t begin_ = 0;            // next unread byte in buffer_
  size_t end_ = 0;              // one past the last valid byte in buffer_
  uint64_t limit_ = UINT64_MAX;
  bool partial_ = false;
  uint64_t partial_offset_ = 0;
  int partial_declared_size_ = 0;
};

}  // namespace mavloc::ulog
