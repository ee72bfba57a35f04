// SPDX-License-Identifier: Apache-2.0
// Test harness for ethercat_tests: a veth pair whose slave end lives in its own network
// namespace, with codrive-ecat-sim answering there and a master on the host end.
#pragma once

#include <codrive/ethercat/master.hpp>
#include <codrive/ethercat/raw_socket_link.hpp>
#include <codrive/testing/process.hpp>

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::testing {

/// True if CODRIVE_SKIP_ETHERCAT=1: tests that cannot create a veth pair are skipped instead of
/// failing.
bool ethercat_skip_requested();

/// A veth pair "ecmP<n>" (host, master side) / "ecsP<n>" (inside netns "codrive-ecat-P-<n>").
class VethPair {
public:
    VethPair();
    ~VethPair();
    VethPair(const VethPair&) = delete;
    VethPair& operator=(const VethPair&) = delete;

    /// Creates everything; false with `error()` explaining why (not root, no veth support).
    bool create();
    [[nodiscard]] const std::string& error() const { return error_; }
    [[nodiscard]] const std::string& master_if() const { return master_if_; }
    [[nodiscard]] const std::string& slave_if() const { return slave_if_; }
    [[nodiscard]] const std::string& netns() const { return netns_; }
    /// `ip link set <master_if> up|down`: a master whose interface is taken away (an unplugged
    /// USB adapter, a network manager) sees ENETDOWN from send and receive. False with
    /// `error()` if `ip` fails.
    bool set_master_up(bool up);
    /// `tc qdisc add dev <master_if> root tbf ...` so slow that the interface's transmit queue
    /// is full after a few dozen frames and stays full (a NIC whose transmission hangs): sends
    /// then fail with ENOBUFS. False with `error()` if `tc` fails.
    bool choke_master_queue();

private:
    std::string master_if_;
    std::string slave_if_;
    std::string netns_;
    std::string error_;
    bool created_ = false;
};

/// Path of codrive-ecat-sim.
std::string ecat_sim_path();

/// Fixture: veth pair + simulator (arguments after --ethercat IFACE) + master on the host end.
class EcatVethTest : public ::testing::Test {
protected:
    /// Starts the simulator with `sim_args` and opens the master link. Fails the test (or skips
    /// with CODRIVE_SKIP_ETHERCAT=1) when veth cannot be created.
    /// `program` is codrive-ecat-sim, or codrive-sim, which hands `--ethercat` over to it.
    void start(const std::vector<std::string>& sim_args,
               const std::string& program = ecat_sim_path());
    /// start(), then for a test whose controller (or program) opens its own socket: the
    /// fixture's master and link closed, and the simulator at real-time priority, as a slave's
    /// ESC answers (a loaded host then does not turn its late answers into lost frames).
    void start_for_controller(const std::vector<std::string>& sim_args);
    /// Writes `text` to /tmp/codrive-ecat-<tag>-<pid>[-<master interface>]-<n>.yml and returns
    /// the path; TearDown() removes every file written so. `n` counts this fixture's files, so
    /// two files of one test never collide; the master interface (once start() made the veth
    /// pair) keeps the names of tests running in parallel processes apart.
    std::string write_temp_file(std::string_view tag, const std::string& text);
    /// The fixture's own steps, then every file of write_temp_file() removed.
    void TearDown() override;

    std::unique_ptr<VethPair> veth_;
    std::unique_ptr<Process> sim_;
    std::unique_ptr<ethercat::RawSocketLink> link_;
    std::unique_ptr<ethercat::Master> master_;

private:
    std::vector<std::string> temp_files_;
};

} // namespace codrive::testing
