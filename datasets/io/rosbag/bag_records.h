// A walk over the top-level records of a ROS1 bag (format 2.0,
// http://wiki.ros.org/Bags/Format/2.0): each record is <uint32 header_len><header><uint32
// data_len><data>, the header a list of <uint32 len><name>=<value> fields (parsed with ros::Header,
// the same code rosbag uses). Only the headers are read, the data are skipped, so the walk costs
// one seek per record (chunks hold the messages; the walk does not enter them). rosbag::Bag does
// not expose chunk headers; this walk gives the summary its compression kinds and locates the byte
// where a truncated bag ends.
//
// It also checks what rosbag::Bag trusts without checking (a corrupt length makes it allocate
// gigabytes before the read fails: found by fuzz_rosbag): every record fits in the file, the bag
// header's index position is the start of a record, every chunk-info record points at a chunk,
// a chunk's uncompressed size is plausible (at most kMaxChunkBytes; equal to its data for an
// uncompressed chunk) and an index-data record holds the entries it counts. OpenedBag walks a bag
// before rosbag opens it and refuses one with a problem.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "core/input_limits.h"

namespace mavloc::ros1 {

struct BagRecordScan {
  uint64_t file_bytes = 0;
  uint64_t index_pos = 0;  // from the bag header record; 0 when the bag was never closed
  uint64_t chunks = 0;
  std::map<std::string, uint64_t> chunks_by_compression;  // "none", "bz2", "lz4"
  // The walk stopped at `end_offset`: equal to file_bytes for a complete file, else the byte where
  // a record is cut off (truncated) or unreadable (corrupt), described by `problem`.
  uint64_t end_offset = 0;
  std::string problem;
};

constexpr uint64_t kMaxChunkBytes = input_limits::kMaxBagChunkBytes;  // core/input_limits.h

// Throws InputError when the file cannot be opened or does not start with "#ROSBAG V2.0\n".
BagRecordScan ScanBagRecords(const std::string& path);

}  // namespace mavloc::ros1
