// Shared helpers for the test suites: central-difference Jacobians (the one helper every analytic
// Jacobian is checked with, DESIGN.md "Conventions"), paths to the shared real data and the CLI,
// and a temporary folder per test.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>

namespace mavloc::testing {

// J(i, j) = d f_i / d x_j by central differences (f(x + h e_j) - f(x - h e_j)) / 2h.
Eigen::MatrixXd CentralDifferenceJacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
    double step = 1e-6);

// Same, with a user-supplied perturbation (boxplus) x (+) delta and difference f(a) (-) f(b), for
// manifold states: J(:, j) = (f(x (+) h e_j) (-) f(x (+) -h e_j)) / 2h.
Eigen::MatrixXd CentralDifferenceJacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd& delta)>& f_of_delta, int delta_dim,
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&, const Eigen::VectorXd&)>& minus,
    double step = 1e-6);

// The suites run the CLI with MAVLOC_FIGURES=0 (set when the suite starts, unless the environment
// sets it); a suite that checks figures calls FiguresOn() first.
void FiguresOn();

// ../shared/data (absolute), and whether it exists.
std::string SharedDataDir();
bool HasSharedData();
// The mavloc executable built alongside the tests, and the source tree it was built from (for the
// schemas and scripts the tests use).
std::string CliPath();
std::string SourceDir();
// A fresh, empty folder under the system temp dir, unique to the running test.
std::string MakeTempDir();
// A file's bytes (empty when it cannot be read), and (over)writing a file with the given bytes: the
// bad-input suites read real files, mutate them and write the copies.
std::string ReadFileBytes(const std::string& path);
void WriteFileBytes(const std::string& path, const std::string& bytes);

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr interleaved
};
// Runs a shell command (with MAVLOC_QUIET=1) and captures its output.
CommandResult RunCommand(const std::string& command);

// Runs `mavloc ARGS` in `dir` (MAVLOC_QUIET=1, MAVLOC_FIGURES=0) with stdout and stderr kept
// apart (their files in `dir` are removed afterwards), for the bad-input suites that count stderr
// lines.
struct CliRun {
  int exit_code = -1;
  std::string out, err;
};
CliRun RunCliIn(const std::string& dir, const std::string& args);

}  // namespace mavloc::testing

// Skips the test with a message when ../shared/data (the real logs) is absent.
#define REQUIRE_SHARED_DATA() \
  if (!::mavloc::testing::HasSharedData()) GTEST_SKIP() << "../shared/data is absent"
