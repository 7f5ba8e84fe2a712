// A real Slurm: starts a one-node cluster in a temporary
// folder (Debian's slurm-wlm 22.05 and munge; munged with its own key, socket and pid files,
// slurmctld and slurmd with a generated slurm.conf: cons_tres, proctrack/linuxproc, task/none, no
// cgroups, no accounting, state and spool in the folder, NodeName=localhost with this machine's
// CPUs and memory, SlurmUser=root), submits a small sweep with `mavloc sweep --slurm`, waits for
// the array and the merge job (polling squeue, with a timeout), and checks that the merged report
// is the local run's, byte for byte. Every daemon it started is stopped, also on failure (the
// cluster object's destructor). Skips with a message when not root, when the daemons are not
// installed, or when the cluster does not come up.
#include <fcntl.h>
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <regex>
#include <thread>

#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mavloc {
namespace {

using testing::CliPath;
using testing::RunCommand;

std::string Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

int FreeTcpPort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  socklen_t length = sizeof(address);
  int port = -1;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0)
    port = ntohs(address.sin_port);
  ::close(fd);
  return port;
}

class LocalSlurm {
 public:
  explicit LocalSlurm(std::string dir) : dir_(std::move(dir)) {}
  ~LocalSlurm() { Stop(); }

  // Returns an empty string when the cluster is up, else why not.
  std::string Start() {
    // munge: a fresh key, our own socket.
    {
      std::ofstream key(dir_ + "/munge.key", std::ios::binary);
      std::random_device random;
      for (int i = 0; i < 1024; ++i) key.put(static_cast<char>(random() & 0xff));
    }
    fs::permissions(dir_ + "/munge.key", fs::perms::owner_read, fs::perm_options::replace);
    const std::string socket = dir_ + "/munge.sock";
    Spawn({"/usr/sbin/munged", "-F", "-f", "--key-file=" + dir_ + "/munge.key",
           "--socket=" + socket, "--pid-file=" + dir_ + "/munged.pid",
           "--seed-file=" + dir_ + "/munged.seed", "--log-file=" + dir_ + "/munged.log"},
          dir_ + "/munged.out");
    if (!WaitFor([&] { return fs::exists(socket); }, 10))
      return "munged did not start: " + Read(dir_ + "/munged.out");

    const long memory_mb = ::sysconf(_SC_PHYS_PAGES) * ::sysconf(_SC_PAGESIZE) / (1024 * 1024);
    const long cpus = ::sysconf(_SC_NPROCESSORS_ONLN);
    fs::create_directories(dir_ + "/state");
    fs::create_directories(dir_ + "/spool");
    std::ofstream conf(dir_ + "/slurm.conf");
    conf << "ClusterName=mavloctest\nSlurmctldHost=localhost(127.0.0.1)\n"
         << "SlurmUser=root\nSlurmdUser=root\n"
         << "SlurmctldPort=" << FreeTcpPort() << "\nSlurmdPort=" << FreeTcpPort() << "\n"
         << "AuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket=" << socket << "\n"
         << "StateSaveLocation=" << dir_ << "/state\nSlurmdSpoolDir=" << dir_ << "/spool\n"
         << "SlurmctldPidFile=" << dir_ << "/slurmctld.pid\nSlurmdPidFile=" << dir_
         << "/slurmd.pid\n"
         << "SlurmctldLogFile=" << dir_ << "/slurmctld.log\nSlurmdLogFile=" << dir_
         << "/slurmd.log\n"
         << "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n"
         << "JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\n"
         << "SelectType=select/cons_tres\nSelectTypeParameters=CR_CPU\n"
         << "SchedulerType=sched/builtin\nReturnToService=2\nMpiDefault=none\n"
         << "NodeName=localhost NodeAddr=127.0.0.1 CPUs=" << cpus << " RealMemory=" << memory_mb / 2
         << " State=UNKNOWN\n"
         << "PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n";
    conf.close();
    // Every slurm command of this process and its children (mavloc, sbatch, the jobs) uses it.
    ::setenv("SLURM_CONF", (dir_ + "/slurm.conf").c_str(), 1);
    Spawn({"/usr/sbin/slurmctld", "-D", "-f", dir_ + "/slurm.conf"}, dir_ + "/slurmctld.out");
    Spawn({"/usr/sbin/slurmd", "-D", "-N", "localhost", "-f", dir_ + "/slurm.conf"},
          dir_ + "/slurmd.out");
    if (!WaitFor([] { return RunCommand("sinfo -h -o %T").output.find("idle") == 0; }, 30))
      return "the node did not become idle: " + RunCommand("sinfo 2>&1").output +
             Read(dir_ + "/slurmctld.out") + Read(dir_ + "/slurmd.out") +
             Tail(dir_ + "/slurmctld.log") + Tail(dir_ + "/slurmd.log");
    return "";
  }

  void Stop() {
    if (pids_.empty()) return;
    RunCommand("scancel --user=root");  // only this cluster: SLURM_CONF points at it
    for (auto it = pids_.rbegin(); it != pids_.rend(); ++it) ::kill(-*it, SIGTERM);
    for (const pid_t pid : pids_) {
      bool gone = false;
      for (int i = 0; i < 50 && !gone; ++i) {
        gone = ::waitpid(pid, nullptr, WNOHANG) == pid;
        if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      if (!gone) {
        ::kill(-pid, SIGKILL);
        ::waitpid(pid, nullptr, 0);
      }
    }
    pids_.clear();
    ::unsetenv("SLURM_CONF");
  }

  std::string Logs() const { return Tail(dir_ + "/slurmctld.log") + Tail(dir_ + "/slurmd.log"); }

 private:
  static std::string Tail(const std::string& path) {
    const std::string text = Read(path);
    return "--- " + path + ":\n" + (text.size() > 3000 ? text.substr(text.size() - 3000) : text);
  }

  template <typename Condition>
  static bool WaitFor(Condition condition, int seconds) {
    for (int i = 0; i < seconds * 5; ++i) {
      if (condition()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    return false;
  }

  // Starts a daemon in the foreground, in its own process group (so that Stop reaches whatever it
  // forked), output to a file.
  void Spawn(const std::vector<std::string>& argv, const std::string& output) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::setpgid(0, 0);
      const int fd = ::open(output.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        ::dup2(fd, STDOUT_FILENO);
        ::dup2(fd, STDERR_FILENO);
      }
      std::vector<char*> args;
      for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      ::execv(args[0], args.data());
      ::_exit(127);
    }
    if (pid > 0) {
      ::setpgid(pid, pid);
      pids_.push_back(pid);
    }
  }

  std::string dir_;
  std::vector<pid_t> pids_;
};

TEST(SlurmSweep, JobArrayAndMergeJobGiveTheLocalBytes) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to start slurmctld, slurmd and munged";
  for (const char* tool : {"/usr/sbin/munged", "/usr/sbin/slurmctld", "/usr/sbin/slurmd",
                           "/usr/bin/sbatch", "/usr/bin/squeue", "/usr/bin/sinfo"})
    if (!fs::exists(tool))
      GTEST_SKIP() << tool << " is not installed (scripts/setup installs slurm-wlm and munge)";
  if (!fs::exists(CliPath())) GTEST_SKIP() << "the mavloc executable is not built: " << CliPath();
  // A short folder name: munge and slurm put socket paths in it.
  std::string dir = (fs::temp_directory_path() / "mavloc_slurm_XXXXXX").string();
  ASSERT_NE(::mkdtemp(dir.data()), nullptr);
  struct Cleanup {
    std::string dir;
    ~Cleanup() { fs::remove_all(dir); }
  } cleanup{dir};
  LocalSlurm slurm(dir);
  const std::string why = slurm.Start();
  if (!why.empty()) GTEST_SKIP() << "could not start a local Slurm: " << why.substr(0, 4000);

  const std::string grid =
      "--scenario tag-arena-hover --duration 2 --seeds 1..4 --set corner_noise_px=0.3,1 "
      "--estimators tag-pnp,tag-ekf";
  auto r = RunCommand(CliPath() + " sweep " + grid + " --slurm --shards 3 --time 00:05:00 " +
                      "--cpus-per-task 1 --out " + dir + "/results");
  ASSERT_EQ(r.exit_code, 0) << r.output << slurm.Logs();
  std::smatch match;
  ASSERT_TRUE(std::regex_search(
      r.output, match,
      std::regex(R"(submitted array job ([0-9]+) \(3 tasks\) and merge job ([0-9]+) \(afterok:)")))
      << r.output;
  const std::string jobs = match[1].str() + "," + match[2].str();
  // The local run meanwhile (same binary, same grid).
  const auto local = RunCommand(CliPath() + " sweep " + grid + " --jobs 1 --out " + dir + "/local");
  ASSERT_EQ(local.exit_code, 0) << local.output;

  const auto start = std::chrono::steady_clock::now();
  bool done = false;
  while (!done && std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
    const auto queue = RunCommand("squeue -h -j " + jobs + " -o %i");
    done = queue.exit_code == 0 && queue.output.empty();
    if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  std::string logs;
  for (const auto& entry : fs::directory_iterator(dir + "/results/logs"))
    logs += "--- " + entry.path().string() + ":\n" + Read(entry.path().string());
  ASSERT_TRUE(done) << "jobs still queued after 60 s\n"
                    << RunCommand("squeue").output << logs << slurm.Logs();
  for (const char* name : {"report.md", "report.json", "runs.csv"}) {
    std::string merged = Read(dir + "/results/report/" + name);
    std::string local = Read(dir + "/local/" + name);
    EXPECT_FALSE(merged.empty()) << name << " missing from the merged report\n" << logs;
    if (std::string(name) == "report.json") {  // all but the provenance (command, elapsed time)
      nlohmann::json m = nlohmann::json::parse(merged), l = nlohmann::json::parse(local);
      m.erase("provenance");
      l.erase("provenance");
      merged = m.dump();
      local = l.dump();
    }
    if (std::string(name) == "report.md") {  // the figures note names each report's own folder
      merged = merged.substr(0, merged.find("<!-- mavloc:figures -->"));
      local = local.substr(0, local.find("<!-- mavloc:figures -->"));
    }
    EXPECT_TRUE(merged == local) << name << " differs\n" << logs;
  }
  const auto status = RunCommand(CliPath() + " sweep-status " + dir + "/results");
  EXPECT_EQ(status.exit_code, 0) << status.output;
  EXPECT_NE(status.output.find("3 of 3 shards complete"), std::string::npos) << status.output;
  slurm.Stop();
}

}  // namespace
}  // namespace mavloc
