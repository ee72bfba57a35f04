// SPDX-License-Identifier: Apache-2.0
// Child process helper for tests (fork/exec with output captured to a temp file).
#include <codrive/testing/process.hpp>

#include <cerrno>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace codrive::testing {

Process::Process(std::vector<std::string> argv) {
    char tmpl[] = "/tmp/codrive-proc-XXXXXX";
    int out_fd = mkstemp(tmpl);
    if (out_fd < 0) {
        throw std::runtime_error("mkstemp failed");
    }
    out_path_ = tmpl;
    pid_ = fork();
    if (pid_ < 0) {
        close(out_fd);
        throw std::runtime_error("fork failed");
    }
    if (pid_ == 0) {
        dup2(out_fd, 1);
        dup2(out_fd, 2);
        int null_fd = open("/dev/null", O_RDONLY);
        if (null_fd >= 0) {
            dup2(null_fd, 0);
        }
        std::vector<char*> args;
        args.reserve(argv.size() + 1);
        for (auto& a : argv) {
            args.push_back(a.data());
        }
        args.push_back(nullptr);
        execv(args[0], args.data());
        _exit(127);
    }
    close(out_fd);
}

Process::~Process() {
    if (running()) {
        ::kill(pid_, SIGKILL);
        wait(std::chrono::milliseconds(2000));
    }
    if (!out_path_.empty()) {
        ::unlink(out_path_.c_str());
    }
}

void Process::signal(int sig) {
    if (pid_ > 0 && !status_) {
        ::kill(pid_, sig);
    }
}

bool Process::running() {
    if (status_ || pid_ <= 0) {
        return false;
    }
    int st = 0;
    pid_t r = waitpid(pid_, &st, WNOHANG);
    if (r == pid_) {
        status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        return false;
    }
    return true;
}

std::optional<int> Process::wait(std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (running()) {
        if (std::chrono::steady_clock::now() >= end) {
            return std::nullopt;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return status_;
}

std::string Process::output() const {
    std::ifstream in(out_path_);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

bool Process::wait_for_output(const std::string& text, std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
        if (output().find(text) != std::string::npos) {
            return true;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return output().find(text) != std::string::npos;
}

RunResult run(std::vector<std::string> argv, std::chrono::milliseconds timeout) {
    Process p(std::move(argv));
    RunResult r;
    auto st = p.wait(timeout);
    if (!st) {
        p.signal(SIGKILL);
        st = p.wait(std::chrono::milliseconds(2000));
        r.output = p.output() + "\n[timed out]";
        r.status = -1;
        return r;
    }
    r.status = *st;
    r.output = p.output();
    return r;
}

std::string tool_path(const std::string& name) {
    if (const char* dir = std::getenv("CODRIVE_TOOLS_DIR")) {
        return std::string(dir) + "/" + name;
    }
    return std::string(CODRIVE_BUILD_DIR) + "/tools/" + name;
}

std::string example_path(const std::string& name) {
    return std::string(CODRIVE_BUILD_DIR) + "/examples/codrive-" + name;
}

std::string self_exe() {
    char buf[PATH_MAX];
    const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof(buf) - 1);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
}

} // namespace codrive::testing
