// Limits on the structure of input files, in one place (docs/limits.md lists them).
//
// A few bytes of a crafted file can describe a structure that is expensive to expand: a ULog
// format that nests arrays of other formats, a ROS array whose length field claims millions of
// elements, YAML aliases that repeat a large node. Every reader checks the limits below before it
// does the work or allocates, so the work per input byte stays bounded; a file beyond a limit is
// refused with an InputError naming the file, the structure and the limit. The limits sit far
// above anything a real log or configuration file holds (the reason is stated beside each one).
#pragma once

#include <cstdint>

namespace mavloc::input_limits {

// ---- ULog formats ('F' messages, datasets/io/ulog/ulog_format.h)
// Nesting depth of one format's nested types. PX4's formats nest 2-3 levels.
inline constexpr int kMaxUlogFormatNesting = 16;
// Flattened fields of one format: primitive fields after every nested type and array is expanded,
// an element of an empty nested format counting as one (it still costs a step to expand). A
// message's size field is 16 bits and every primitive takes a byte or more, so a real format
// never has more.
inline constexpr uint64_t kMaxUlogFormatFields = 65535;
// Flattened bytes of one format: the largest payload a ULog message can carry (16-bit size).
inline constexpr uint64_t kMaxUlogFormatBytes = 65535;
// Flattening work for one whole log: every format field visited while checking a subscription's
// format and every flattened field kept, summed over all subscriptions ('A' messages). The real
// PX4 logs of the shared data (43-72 subscriptions) need 1,700-2,400 steps; this bounds a file of
// many subscriptions to large formats to about a second and 100 MB.
inline constexpr uint64_t kMaxUlogFlattenWork = uint64_t{1} << 21;

// ---- ROS1 bags (datasets/io/rosbag)
// Uncompressed size of one chunk: rosbag writes chunks of about 768 kB.
inline constexpr uint64_t kMaxBagChunkBytes = uint64_t{1} << 30;
// While a message of n bytes is deserialized, an array may hold at most n / w elements, w being
// the fewest bytes one element takes on the wire (1 for uint8, 8 for float64, 368 for an
// AprilTagDetection): a corrupt length is refused before it is allocated (ros_messages.h).

// ---- YAML (datasets/io/yaml_util.h)
// Nesting depth of a YAML document (maps and lists within each other). Calibration and map files
// nest 3-6 levels; yaml-cpp's parser itself stops at 500.
inline constexpr int kMaxYamlNesting = 64;
// Nodes of a YAML document, counting a node once per alias that repeats it (what a reader that
// walks the document would visit): the largest real file (a TagSLAM map) has a few thousand.
inline constexpr uint64_t kMaxYamlNodes = uint64_t{1} << 20;

// ---- Images (core/image_check.h)
// Pixels of one image (width x height): 2^28 is 16384 x 16384, far above any camera mavloc reads.
inline constexpr uint64_t kMaxImagePixels = uint64_t{1} << 28;

}  // namespace mavloc::input_limits
