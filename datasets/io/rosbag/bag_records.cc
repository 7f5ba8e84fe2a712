#include "datasets/io/rosbag/bag_records.h"

#include <fmt/format.h>
#include <ros/header.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "core/errors.h"

namespace mavloc::ros1 {

namespace {

constexpr char kMagic[] = "#ROSBAG V2.0\n";
constexpr uint64_t kMagicBytes = sizeof(kMagic) - 1;
constexpr uint32_t kMaxHeaderBytes = 1u << 24;  // record headers are a few hundred bytes

constexpr uint8_t kOpBagHeader = 0x03;
constexpr uint8_t kOpChunk = 0x05;

bool ReadUint32(std::ifstream& in, uint32_t* value) {
  unsigned char bytes[4];
  if (!in.read(reinterpret_cast<char*>(bytes), 4)) return false;
  *value = static_cast<uint32_t>(bytes[0]) | static_cast<uint32_t>(bytes[1]) << 8 |
           static_cast<uint32_t>(bytes[2]) << 16 | static_cast<uint32_t>(bytes[3]) << 24;
  return true;
}

}  // namespace

BagRecordScan ScanBagRecords(const std::string& path) {
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
  while (offset < scan.file_bytes) {
    scan.end_offset = offset;
    uint32_t header_len = 0;
    if (!ReadUint32(in, &header_len) || offset + 4 + header_len > scan.file_bytes) {
      scan.problem = fmt::format("a record at byte {} is cut off (truncated file)", offset);
      return scan;
    }
    if (header_len > kMaxHeaderBytes) {
      scan.problem = fmt::format("the record at byte {} has an implausible header length {}",
                                 offset, header_len);
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
      std::string index_pos;
      if (header.getValue("index_pos", index_pos) && index_pos.size() == 8) {
        std::memcpy(&scan.index_pos, index_pos.data(), 8);  // little-endian, as the host
      }
    } else if (opcode == kOpChunk) {
      std::string compression = "none";
      header.getValue("compression", compression);
      ++scan.chunks;
      ++scan.chunks_by_compression[compression];
    }
    offset += 8 + uint64_t{header_len} + data_len;
    in.seekg(static_cast<std::streamoff>(offset));
  }
  scan.end_offset = offset;
  return scan;
}

}  // namespace mavloc::ros1
