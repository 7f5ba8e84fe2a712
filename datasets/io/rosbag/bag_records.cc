#include "datasets/io/rosbag/bag_records.h"

#include <fmt/format.h>
#include <ros/header.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/input_file.h"

namespace mavloc::ros1 {

namespace {

constexpr char kMagic[] = "#ROSBAG V2.0\n";
constexpr uint64_t kMagicBytes = sizeof(kMagic) - 1;
constexpr uint32_t kMaxHeaderBytes = 1u << 24;  // record headers are a few hundred bytes

constexpr uint8_t kOpBagHeader = 0x03;
constexpr uint8_t kOpIndexData = 0x04;
constexpr uint8_t kOpChunk = 0x05;
constexpr uint8_t kOpChunkInfo = 0x06;
constexpr uint64_t kIndexEntryBytes = 12;  // index data version 1: uint64 time + uint32 offset

// A little-endian integer field of `bytes` bytes; false when absent or of another size.
bool HeaderInteger(const ros::Header& header, const std::string& name, size_t bytes,
                   uint64_t* value) {
  std::string text;
  if (!header.getValue(name, text) || text.size() != bytes) return false;
  *value = 0;
  for (size_t i = 0; i < bytes; ++i)
    *value |= static_cast<uint64_t>(static_cast<unsigned char>(text[i])) << (8 * i);
  return true;
}

// Whether every <uint32 len><name>=<value> field of a record header lies inside it:
// ros::Header::parse copies a field of the length it reads without checking it against the
// header's (found by fuzz_rosbag: a heap-buffer-overflow in libcpp_common), so it only sees
// headers that pass this check.
bool HeaderFieldsFit(const std::vector<uint8_t>& bytes) {
  size_t at = 0;
  while (at < bytes.size()) {
    if (bytes.size() - at < 4) return false;
    const uint32_t length =
        static_cast<uint32_t>(bytes[at]) | static_cast<uint32_t>(bytes[at + 1]) << 8 |
        static_cast<uint32_t>(bytes[at + 2]) << 16 | static_cast<uint32_t>(bytes[at + 3]) << 24;
    at += 4;
    if (length > bytes.size() - at) return false;
    at += length;
  }
  return true;
}

bool ReadUint32(std::ifstream& in, uint32_t* value) {
  unsigned char bytes[4];
  if (!in.read(reinterpret_cast<char*>(bytes), 4)) return false;
  *value = static_cast<uint32_t>(bytes[0]) | static_cast<uint32_t>(bytes[1]) << 8 |
           static_cast<uint32_t>(bytes[2]) << 16 | static_cast<uint32_t>(bytes[3]) << 24;
  return true;
}

// The chunk the index-data records after it point into (bag format 2.0 writes a chunk, then one
// index-data record per connection in it).
struct ChunkSpan {
  uint64_t data_start = 0;  // file offset of the chunk's data
  uint64_t size = 0;        // uncompressed size
  bool compressed = false;
};

// Checks every entry (uint32 sec, uint32 nsec, uint32 offset) of an index-data record at
// `entries_start` against its chunk: rosbag reads the message record at the entry's offset in the
// chunk's uncompressed data without checking it against the chunk's size (found by fuzz_rosbag: a
// SEGV in rosbag::Bag::readHeaderFromBuffer). In an uncompressed chunk the message record itself
// (<uint32 header_len><header><uint32 data_len><data>) must fit, and its header fields too; in a
// compressed one only the offset can be checked here. Returns the problem, or "".
std::string CheckIndexEntries(std::ifstream& in, uint64_t record_offset, uint64_t entries_start,
                              uint64_t count, const ChunkSpan& chunk) {
  std::vector<uint8_t> header_bytes;
  for (uint64_t i = 0; i < count; ++i) {
    in.seekg(static_cast<std::streamoff>(entries_start + i * kIndexEntryBytes + 8));
    uint32_t at = 0;
    if (!ReadUint32(in, &at))
      return fmt::format("the index record at byte {} is cut off", record_offset);
    const auto bad = [&](const char* what) {
      return fmt::format(
          "the index record at byte {} points at a message {} of its chunk ({} bytes; entry {}, "
          "offset {})",
          record_offset, what, chunk.size, i, at);
    };
    if (uint64_t{at} + 8 > chunk.size) return bad("beyond the end");
    if (chunk.compressed) continue;
    in.seekg(static_cast<std::streamoff>(chunk.data_start + at));
    uint32_t header_len = 0, data_len = 0;
    if (!ReadUint32(in, &header_len) || uint64_t{at} + 8 + header_len > chunk.size)
      return bad("whose header runs past the end");
    header_bytes.resize(header_len);
    in.read(reinterpret_cast<char*>(header_bytes.data()), header_len);
    if (!in || !HeaderFieldsFit(header_bytes)) return bad("with a corrupt header");
    if (!ReadUint32(in, &data_len) || uint64_t{at} + 8 + header_len + data_len > chunk.size)
      return bad("whose data run past the end");
  }
  return "";
}

}  // namespace

BagRecordScan ScanBagRecords(const std::string& path) {
  RequireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the bag");
  BagRecordScan scan;
  scan.file_bytes = std::filesystem::file_size(path);
  char magic[kMagicBytes] = {};
  if (!in.read(magic, kMagicBytes) || std::memcmp(magic, kMagic, kMagicBytes) != 0) {
    throw InputError(path, 0, "", "not a ROS1 bag (no \"#ROSBAG V2.0\" line at byte 0)");
  }
  uint64_t offset = kMagicBytes;
  std::vector<uint8_t> header_bytes;
  std::set<uint64_t> record_starts, chunk_starts;
  std::vector<std::pair<uint64_t, uint64_t>> chunk_pointers;  // (chunk-info offset, chunk_pos)
  std::optional<ChunkSpan> last_chunk;
  while (offset < scan.file_bytes) {
    scan.end_offset = offset;
    record_starts.insert(offset);
    uint32_t header_len = 0;
    const bool read = ReadUint32(in, &header_len);
    if (read && header_len > kMaxHeaderBytes) {
      scan.problem = fmt::format("the record at byte {} has an implausible header length {}",
                                 offset, header_len);
      return scan;
    }
    if (!read || offset + 4 + header_len > scan.file_bytes) {
      scan.problem = fmt::format("a record at byte {} is cut off (truncated file)", offset);
      return scan;
    }
    header_bytes.resize(header_len);
    in.read(reinterpret_cast<char*>(header_bytes.data()), header_len);
    uint32_t data_len = 0;
    if (!in || !ReadUint32(in, &data_len) ||
        offset + 8 + uint64_t{header_len} + data_len > scan.file_bytes) {
      scan.problem = fmt::format("a record at byte {} is cut off (truncated file)", offset);
      return scan;
    }
    if (!HeaderFieldsFit(header_bytes)) {
      scan.problem = fmt::format(
          "the record header at byte {} is corrupt (a field runs past the header's {} bytes)",
          offset, header_len);
      return scan;
    }
    ros::Header header;
    std::string error;
    if (!header.parse(header_bytes.data(), header_len, error)) {
      scan.problem = fmt::format("the record header at byte {} is corrupt ({})", offset, error);
      return scan;
    }
    std::string op;
    header.getValue("op", op);
    if (op.size() != 1) {
      scan.problem = fmt::format("the record at byte {} has no valid op field", offset);
      return scan;
    }
    const auto opcode = static_cast<uint8_t>(op[0]);
    if (opcode == kOpBagHeader) {
      HeaderInteger(header, "index_pos", 8, &scan.index_pos);
    } else if (opcode == kOpChunk) {
      std::string compression = "none";
      header.getValue("compression", compression);
      uint64_t size = 0;
      if (!HeaderInteger(header, "size", 4, &size) || size > kMaxChunkBytes ||
          (compression == "none" && size != data_len)) {
        scan.problem = fmt::format(
            "the chunk at byte {} states an implausible uncompressed size ({} bytes of data)",
            offset, data_len);
        return scan;
      }
      ++scan.chunks;
      ++scan.chunks_by_compression[compression];
      chunk_starts.insert(offset);
      last_chunk = ChunkSpan{offset + 8 + uint64_t{header_len}, size, compression != "none"};
    } else if (opcode == kOpChunkInfo) {
      uint64_t chunk_pos = 0;
      if (HeaderInteger(header, "chunk_pos", 8, &chunk_pos))
        chunk_pointers.emplace_back(offset, chunk_pos);
    } else if (opcode == kOpIndexData) {
      uint64_t count = 0;
      if (HeaderInteger(header, "count", 4, &count) && count * kIndexEntryBytes > data_len) {
        scan.problem = fmt::format("the index record at byte {} counts {} entries in {} bytes",
                                   offset, count, data_len);
        return scan;
      }
      uint64_t version = 0;
      if (count > 0 && HeaderInteger(header, "ver", 4, &version) && version == 1) {
        scan.problem =
            last_chunk ? CheckIndexEntries(in, offset, offset + 8 + uint64_t{header_len}, count,
                                           *last_chunk)
                       : fmt::format("the index record at byte {} comes before any chunk", offset);
        if (!scan.problem.empty()) return scan;
      }
    }
    offset += 8 + uint64_t{header_len} + data_len;
    in.seekg(static_cast<std::streamoff>(offset));
  }
  if (scan.index_pos != 0 && scan.index_pos < scan.file_bytes &&
      !record_starts.count(scan.index_pos)) {
    scan.end_offset = scan.index_pos;
    scan.problem =
        fmt::format("the index position {} is not the start of a record (corrupt)", scan.index_pos);
    return scan;
  }
  for (const auto& [info_offset, chunk_pos] : chunk_pointers) {
    if (!chunk_starts.count(chunk_pos)) {
      scan.end_offset = info_offset;
      scan.problem =
          fmt::format("the chunk info at byte {} points at byte {}, which is not a chunk (corrupt)",
                      info_offset, chunk_pos);
      return scan;
    }
  }
  scan.end_offset = offset;
  return scan;
}

}  // namespace mavloc::ros1
