// SPDX-License-Identifier: Apache-2.0
// Child processes for tests that need real peers: spawn, read output, signal, wait.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace codrive::testing {

/// A child process with its stdout+stderr captured to a file. Killed (SIGKILL) on destruction
/// if still running.
class Process {
public:
    /// Starts argv[0] (a path) with the arguments. Throws std::runtime_error if fork/exec fails.
    explicit Process(std::vector<std::string> argv);
    ~Process();
    Process(const Process&) = delete;
    Process& operator=(const Process&) = delete;

    /// Sends a signal (SIGTERM by default).
    void signal(int sig = 15);
    /// Waits up to `timeout` for exit; returns the exit status (128+signal if killed).
    std::optional<int> wait(std::chrono::milliseconds timeout);
    [[nodiscard]] bool running();
    /// Everything the process has written so far.
    [[nodiscard]] std::string output() const;
    /// Waits until output contains `text` or timeout.
    bool wait_for_output(const std::string& text, std::chrono::milliseconds timeout);
    [[nodiscard]] int pid() const { return pid_; }

private:
    int pid_ = -1;
    std::optional<int> status_;
    std::string out_path_;
};

/// Runs a command to completion: exit status and combined output.
struct RunResult {
    int status = -1;
    std::string output;
};
RunResult run(std::vector<std::string> argv,
              std::chrono::milliseconds timeout = std::chrono::milliseconds(30000));

/// Path of a built tool: build_dir/tools/<name> etc.
std::string tool_path(const std::string& name);
/// Path of a built example program: build_dir/examples/codrive-<name>.
std::string example_path(const std::string& name);
/// This test binary (readlink, not "/proc/self/exe" itself: under valgrind that names valgrind).
std::string self_exe();

} // namespace codrive::testing
