#include "datasets/io/ulog/ulog_stream.h"

#include <algorithm>
#include <bit>
#include <cstring>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/input_file.h"
#include "datasets/io/ulog/ulog_format.h"

namespace mavloc::ulog {
namespace {

static_assert(std::endian::native == std::endian::little,
              "ULog is little endian; the decoder memcpy's fields directly");

constexpr uint8_t kMagic[7] = {'U', 'L', 'o', 'g', 0x01, 0x12, 0x35};
// Larger than the largest message (3 + 65535 bytes), so one refill always suffices (a smaller
// buffer is only used for a file smaller than it).
constexpr size_t kBufferBytes = 1 << 20;

}  // namespace

MessageStream::MessageStream(const std::string& path) : path_(path) {
  file_ = OpenRegularFileStream(path);  // a pipe, a device, a loop: refused, never blocks
  if (std::fseek(file_, 0, SEEK_END) == 0) {
    const long size = std::ftell(file_);
    if (size > 0) file_bytes_ = static_cast<uint64_t>(size);
  }
  std::fseek(file_, 0, SEEK_SET);
  // A small file fits whole; a large one streams through kBufferBytes.
  buffer_.resize(static_cast<size_t>(std::min<uint64_t>(kBufferBytes, file_bytes_ + 64)));
  if (Ensure(kHeaderBytes) < static_cast<size_t>(kHeaderBytes)) {
    std::fclose(file_);
    throw InputError(
        path, 0, "",
        fmt::format("truncated ULog header at byte offset {} (the header has 16 bytes)", end_));
  }
  if (std::memcmp(buffer_.data(), kMagic, sizeof(kMagic)) != 0) {
    std::fclose(file_);
    throw InputError(path, 0, "", "not a ULog file (byte offset 0: no 'ULog' magic)");
  }
  version_ = buffer_[7];
  header_timestamp_us_ = ReadUint64(buffer_.data() + 8);
  begin_ = kHeaderBytes;
}

MessageStream::~MessageStream() {
  if (file_ != nullptr) std::fclose(file_);
}

size_t MessageStream::Ensure(size_t n) {
  if (end_ - begin_ >= n) return n;
  if (begin_ > 0) {
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    buffer_offset_ += begin_;
    end_ -= begin_;
    begin_ = 0;
  }
  while (end_ < n) {
    const size_t got = std::fread(buffer_.data() + end_, 1, buffer_.size() - end_, file_);
    if (got == 0) break;
    end_ += got;
  }
  return std::min(n, end_ - begin_);
}

bool MessageStream::Next(RawMessage* message) {
  partial_ = false;
  const uint64_t at = offset();
  const size_t have_header = Ensure(kMessageHeaderBytes);
  if (have_header < static_cast<size_t>(kMessageHeaderBytes)) {
    if (have_header > 0 && at + kMessageHeaderBytes <= limit_) {
      partial_ = true;
      partial_offset_ = at;
      partial_declared_size_ = -1;  // the header itself is cut
    }
    return false;
  }
  const uint8_t* header = buffer_.data() + begin_;
  const int size = ReadUint16(header);
  const char type = static_cast<char>(header[2]);
  const uint64_t message_end = at + kMessageHeaderBytes + static_cast<uint64_t>(size);
  if (message_end > limit_) return false;
  if (Ensure(kMessageHeaderBytes + size) < static_cast<size_t>(kMessageHeaderBytes + size)) {
    partial_ = true;
    partial_offset_ = at;
    partial_declared_size_ = size;
    return false;
  }
  message->type = type;
  message->offset = at;
  message->data = buffer_.data() + begin_ + kMessageHeaderBytes;
  message->size = size;
  begin_ += kMessageHeaderBytes + size;
  return true;
}

void MessageStream::Seek(uint64_t offset) {
  if (offset >= buffer_offset_ && offset <= buffer_offset_ + end_) {
    begin_ = static_cast<size_t>(offset - buffer_offset_);
    return;
  }
  std::fseek(file_, static_cast<long>(offset), SEEK_SET);
  buffer_offset_ = offset;
  begin_ = end_ = 0;
}

bool MessageStream::SeekPastSync(uint64_t from) {
  Seek(from);
  constexpr size_t kMagicBytes = sizeof(kSyncMagic);
  while (true) {
    const size_t have = Ensure(kBufferBytes / 2);
    if (have < kMagicBytes) return false;
    const uint8_t* start = buffer_.data() + begin_;
    const uint8_t* found = std::search(start, start + have, kSyncMagic, kSyncMagic + kMagicBytes);
    if (found != start + have) {
      begin_ += static_cast<size_t>(found - start) + kMagicBytes;
      return true;
    }
    // Keep the last 7 bytes: the magic may straddle the refill.
    begin_ += have - (kMagicBytes - 1);
  }
}

}  // namespace mavloc::ulog
