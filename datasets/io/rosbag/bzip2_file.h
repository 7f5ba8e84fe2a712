// Whole-file bzip2 (as TagSLAM ships its bags: "tag_detections.bag.bz2"), decompressed with
// libbz2's streaming interface (bzlib.h, BZ2_bzRead*), one buffer at a time: memory stays bounded
// whatever the file size. Concatenated streams (pbzip2, lbzip2) are decompressed one after the
// other.
#pragma once

#include <cstddef>
#include <string>

namespace mavloc::ros1 {

// True when the file starts with bzip2's magic "BZh".
bool IsBzip2File(const std::string& path);

// Up to `max_bytes` decompressed bytes from the start of a bzip2 file; empty when the file is not
// bzip2 or cannot be read.
std::string ReadBzip2Prefix(const std::string& path, std::size_t max_bytes);

// Decompresses `bz2_path` into `out_path` (created or overwritten). Throws InputError naming
// bz2_path and the number of decompressed bytes when the stream is truncated or corrupt, and
// removes out_path then.
void DecompressBzip2File(const std::string& bz2_path, const std::string& out_path);

}  // namespace mavloc::ros1
