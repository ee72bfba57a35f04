// SPDX-License-Identifier: Apache-2.0
// For the codrive-dump host tests: a scratch directory where documented commands run as a user
// types them (the built tools first on PATH), and the command blocks docs/codrive-dump.md marks.
#pragma once

#include <codrive/testing/process.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace codrive::testing::dump {

inline const std::string kSource = CODRIVE_SOURCE_DIR;

/// A scratch directory with `tests` linked to the source tree's, so the documented relative
/// paths work and written files land here. Removed at the end.
class Scratch {
public:
    explicit Scratch(const std::string& name) {
        dir_ = std::filesystem::temp_directory_path() /
               ("codrive-dump-" + std::to_string(::getpid()) + "-" + name);
        std::filesystem::create_directories(dir_);
        std::filesystem::create_directory_symlink(kSource + "/tests", dir_ / "tests");
    }
    ~Scratch() {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;
    [[nodiscard]] std::string path() const { return dir_.string(); }

    /// Runs a command line with the built tools first on PATH, in this directory.
    [[nodiscard]] RunResult
    shell(const std::string& command,
          std::chrono::milliseconds timeout = std::chrono::seconds(60)) const {
        const auto tools = std::filesystem::path(tool_path("codrive-dump")).parent_path();
        return run({"/bin/sh", "-c",
                    "PATH='" + tools.string() + "':$PATH; cd '" + path() + "' && " + command},
                   timeout);
    }

private:
    std::filesystem::path dir_;
};

/// The fenced block after the comment naming `test_file` ("run by tests/integration/X.cpp") in
/// docs/codrive-dump.md, one command per line.
inline std::vector<std::string> documented_commands(const std::string& test_file) {
    std::ifstream in(kSource + "/docs/codrive-dump.md");
    std::string line;
    bool marked = false;
    bool inside = false;
    std::vector<std::string> commands;
    while (std::getline(in, line)) {
        if (line.find("run by " + test_file) != std::string::npos) {
            marked = true;
        } else if (marked && line.rfind("```", 0) == 0) {
            if (inside) {
                break;
            }
            inside = true;
        } else if (inside && !line.empty()) {
            commands.push_back(line);
        }
    }
    return commands;
}

} // namespace codrive::testing::dump
