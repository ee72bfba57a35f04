// SPDX-License-Identifier: Apache-2.0
// veth pair + network namespace set-up for the EtherCAT tests, and the simulator process.
#include "veth_segment.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sched.h>
#include <unistd.h>

namespace codrive::testing {

namespace {
std::atomic<int> g_counter{0};
const char* kIp = "/usr/sbin/ip";
const char* kTc = "/usr/sbin/tc";
} // namespace

bool ethercat_skip_requested() {
    const char* v = std::getenv("CODRIVE_SKIP_ETHERCAT");
    return v != nullptr && std::string(v) == "1";
}

std::string ecat_sim_path() {
    return tool_path("codrive-ecat-sim");
}

VethPair::VethPair() {
    const int n = g_counter++;
    const int pid = static_cast<int>(::getpid()) % 100000;
    master_if_ = fmt::format("ecm{}x{}", pid, n);
    slave_if_ = fmt::format("ecs{}x{}", pid, n);
    netns_ = fmt::format("codrive-ecat-{}-{}", pid, n);
}

bool VethPair::create() {
    const auto step = [&](std::vector<std::string> argv) {
        auto r = run(argv, std::chrono::milliseconds(10000));
        if (r.status != 0) {
            std::string cmd;
            for (const auto& a : argv) {
                cmd += a + " ";
            }
            error_ = fmt::format("`{}` failed ({}): {}", cmd, r.status, r.output);
            return false;
        }
        return true;
    };
    if (!step({kIp, "netns", "add", netns_})) {
        return false;
    }
    created_ = true;
    return step({kIp, "link", "add", master_if_, "type", "veth", "peer", "name", slave_if_}) &&
           step({kIp, "link", "set", slave_if_, "netns", netns_}) &&
           step({kIp, "link", "set", master_if_, "up"}) &&
           step({kIp, "netns", "exec", netns_, kIp, "link", "set", slave_if_, "up"}) &&
           step({kIp, "netns", "exec", netns_, kIp, "link", "set", "lo", "up"});
}

bool VethPair::set_master_up(bool up) {
    auto r =
        run({kIp, "link", "set", master_if_, up ? "up" : "down"}, std::chrono::milliseconds(10000));
    if (r.status != 0) {
        error_ = fmt::format("`ip link set {} {}` failed ({}): {}", master_if_, up ? "up" : "down",
                             r.status, r.output);
        return false;
    }
    return true;
}

bool VethPair::choke_master_queue() {
    // A token bucket of 1,600 bytes that refills at one byte a second, with a 1,600-byte queue
    // behind it: a few dozen frames leave, a few dozen wait, then every frame is dropped at
    // the queue (ENOBUFS to the sender) for about a minute per frame.
    auto r = run({kTc, "qdisc", "add", "dev", master_if_, "root", "tbf", "rate", "8bit", "burst",
                  "1600", "limit", "1600"},
                 std::chrono::milliseconds(10000));
    if (r.status != 0) {
        error_ = fmt::format("`tc qdisc add dev {} root tbf ...` failed ({}): {}", master_if_,
                             r.status, r.output);
        return false;
    }
    return true;
}

VethPair::~VethPair() {
    if (created_) {
        run({kIp, "link", "del", master_if_}, std::chrono::milliseconds(5000));
        run({kIp, "netns", "del", netns_}, std::chrono::milliseconds(5000));
    }
}

void EcatVethTest::start(const std::vector<std::string>& sim_args, const std::string& program) {
    veth_ = std::make_unique<VethPair>();
    if (!veth_->create()) {
        if (ethercat_skip_requested()) {
            GTEST_SKIP() << "cannot create a veth pair and CODRIVE_SKIP_ETHERCAT=1: "
                         << veth_->error();
        }
        FAIL() << "cannot create the veth pair for the EtherCAT tests (run as root on the host, "
                  "or set CODRIVE_SKIP_ETHERCAT=1 to skip explicitly): "
               << veth_->error();
    }
    std::vector<std::string> argv{"/usr/sbin/ip", "netns",      "exec",           veth_->netns(),
                                  program,        "--ethercat", veth_->slave_if()};
    argv.insert(argv.end(), sim_args.begin(), sim_args.end());
    sim_ = std::make_unique<Process>(argv);
    ASSERT_TRUE(sim_->wait_for_output("ready", std::chrono::milliseconds(10000)))
        << program << " did not start: " << sim_->output();
    auto link = ethercat::RawSocketLink::open(veth_->master_if());
    ASSERT_TRUE(link) << ethercat::RawSocketLink::describe_open_error(veth_->master_if(),
                                                                      link.error());
    link_ = std::move(*link);
    ethercat::MasterConfig cfg;
    cfg.frame_timeout = std::chrono::milliseconds(50); // sanitizer builds are slow
    master_ = std::make_unique<ethercat::Master>(*link_, RealClock::instance(), cfg);
}

void EcatVethTest::start_for_controller(const std::vector<std::string>& sim_args) {
    start(sim_args);
    master_.reset();
    link_.reset();
    if (sim_) {
        sched_param rt{};
        rt.sched_priority = 50;
        EXPECT_EQ(::sched_setscheduler(sim_->pid(), SCHED_FIFO, &rt), 0);
    }
}

std::string EcatVethTest::write_temp_file(std::string_view tag, const std::string& text) {
    const std::string iface = veth_ ? "-" + veth_->master_if() : std::string();
    const std::string path =
        fmt::format("/tmp/codrive-ecat-{}-{}{}-{}.yml", tag, ::getpid(), iface, temp_files_.size());
    std::ofstream(path) << text;
    temp_files_.push_back(path);
    return path;
}

void EcatVethTest::TearDown() {
    master_.reset();
    link_.reset();
    if (sim_) {
        sim_->signal(15);
        sim_->wait(std::chrono::milliseconds(3000));
        sim_.reset();
    }
    veth_.reset();
    // The bus files written with write_temp_file(), once nothing the test started can read one.
    for (const auto& f : temp_files_) {
        std::remove(f.c_str());
    }
    temp_files_.clear();
}

} // namespace codrive::testing
