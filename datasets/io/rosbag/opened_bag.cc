#include "datasets/io/rosbag/opened_bag.h"

#include <console_bridge/console.h>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <set>

#include "core/errors.h"
#include "core/progress.h"
#include "datasets/io/rosbag/bag_records.h"
#include "datasets/io/rosbag/bzip2_file.h"

namespace mavloc::ros1 {

namespace {

std::string TemporaryBagPath() {
  static std::atomic<int> counter{0};
  const auto folder = std::filesystem::temp_directory_path();
  return (folder / fmt::format("mavloc-bag-{}-{}.bag", static_cast<long>(getpid()), counter++))
      .string();
}

// Why rosbag could not open a bag whose record walk found no problem.
std::string DescribeOpenFailure(const BagRecordScan& scan, const std::string& what) {
  if (scan.index_pos == 0 || scan.index_pos >= scan.file_bytes) {
    return fmt::format("the bag was not closed (index position {} of {} bytes); rosbag: {}",
                       scan.index_pos, scan.file_bytes, what);
  }
  return fmt::format("index at byte {} is unreadable; rosbag: {}", scan.index_pos, what);
}

// ROS's libraries (ros::Header::parse in libcpp_common, rosbag_storage) print their own errors
// through console_bridge to stderr ("Error: Received an invalid TCPROS header..." and the source
// line) before the exception mavloc turns into its one line: their output handler is removed, once,
// before the first bag is read. Every failure still reaches the user as an InputError.
void SilenceRosConsole() {
  static const bool silenced = [] {
    console_bridge::noOutputHandler();
    return true;
  }();
  (void)silenced;
}

}  // namespace

OpenedBag::OpenedBag(const std::string& path) : path_(path), opened_path_(path) {
  SilenceRosConsole();
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(path, 0, "", "no such bag file");
  }
  if (IsBzip2File(path)) {
    temporary_path_ = TemporaryBagPath();
    temporary_guard_ = std::make_unique<TemporaryPathGuard>(temporary_path_);
    DecompressBzip2File(path, temporary_path_);
    opened_path_ = temporary_path_;
  }
  const auto fail = [&](const std::string& description) {
    if (!temporary_path_.empty()) {
      std::error_code ignored;
      std::filesystem::remove(temporary_path_, ignored);
    }
    throw InputError(path, 0, "", (whole_file_bzip2() ? "decompressed bag: " : "") + description);
  };
  // rosbag trusts the lengths and positions it reads (bag_records.h): the record walk first.
  BagRecordScan scan;
  try {
    scan = ScanBagRecords(opened_path_);
  } catch (const InputError& error) {
    fail(error.what());
  }
  if (!scan.problem.empty()) {
    fail(
        fmt::format("{} of {} bytes; not opened (a bag cut off before its index: `rosbag "
                    "reindex` can rebuild the index from a copy)",
                    scan.problem, scan.file_bytes));
  }
  try {
    bag_.open(opened_path_, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& error) {
    fail(DescribeOpenFailure(scan, error.what()));
  }
}

OpenedBag::~OpenedBag() {
  bag_.close();
  if (!temporary_path_.empty()) {
    std::error_code ignored;
    std::filesystem::remove(temporary_path_, ignored);
  }
}

void OpenedBag::Fail(const std::string& topic, uint64_t index, const std::string& message) const {
  throw InputError(path_, 0, "", fmt::format("topic {}, message {}: {}", topic, index, message));
}

std::vector<const rosbag::ConnectionInfo*> OpenedBag::Connections(const std::string& topic) {
  rosbag::View view(bag_, rosbag::TopicQuery(topic));
  std::vector<const rosbag::ConnectionInfo*> connections = view.getConnections();
  if (connections.empty()) {
    rosbag::View all(bag_);
    std::set<std::string> topics;
    for (const rosbag::ConnectionInfo* connection : all.getConnections()) {
      topics.insert(connection->topic);
    }
    std::string list;
    for (const std::string& name : topics) list += (list.empty() ? "" : ", ") + name;
    throw InputError(path_, 0, "",
                     fmt::format("topic {} is not in the bag (topics: {})", topic,
                                 list.empty() ? "none" : list));
  }
  for (const rosbag::ConnectionInfo* connection : connections) {
    if (connection->datatype != connections.front()->datatype) {
      throw InputError(path_, 0, "",
                       fmt::format("topic {} mixes message types {} and {}", topic,
                                   connections.front()->datatype, connection->datatype));
    }
  }
  return connections;
}

std::string OpenedBag::TopicType(const std::string& topic) {
  return Connections(topic).front()->datatype;
}
std::string OpenedBag::TopicMd5(const std::string& topic) {
  return Connections(topic).front()->md5sum;
}
std::string OpenedBag::TopicDefinition(const std::string& topic) {
  return Connections(topic).front()->msg_def;
}

void OpenedBag::ForEachMessage(
    const std::string& topic,
    const std::function<void(const rosbag::MessageInstance&, uint64_t)>& visit) {
  Connections(topic);  // a clear error for a missing topic
  rosbag::View view(bag_, rosbag::TopicQuery(topic));
  const uint64_t total = view.size();
  constexpr uint64_t kReportAbove = 100000;  // messages; shorter topics read in well under a second
  uint64_t index = 0;
  try {
    for (const rosbag::MessageInstance& message : view) {
      visit(message, index);
      ++index;
      if (total > kReportAbove && index % (total / 10) == 0) {
        ReportProgress("bag", fmt::format("{} {}: {}%", path_, topic, 100 * index / total));
      }
    }
  } catch (const InputError& error) {
    if (std::string(error.what()).rfind(path_ + ":", 0) == 0) throw;  // already located
    Fail(topic, index, error.what());
  } catch (const rosbag::BagException& error) {
    Fail(topic, index, std::string("corrupt bag: ") + error.what());
  } catch (const ros::Exception& error) {  // StreamOverrunException: the message is too short
    Fail(topic, index, std::string("cannot deserialize: ") + error.what());
  }
}

}  // namespace mavloc::ros1
