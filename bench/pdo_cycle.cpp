// SPDX-License-Identifier: Apache-2.0
// Cost of one SYNC cycle of the master PDO engine (16 nodes × 2 RPDO + 2 TPDO) next to a
// hand-written memcpy floor; run under callgrind by pdo_cycle.sh for instructions per cycle.
#include <codrive/core/can_bus.hpp>
#include <codrive/pdo/master.hpp>

#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <new>

#include <codrive/testing/counting_new.hpp>
#include <string>
#include <vector>

// One program-wide counting operator new (included once per program).
using codrive::testing::g_allocations;
using codrive::testing::g_counting;

namespace {

using namespace codrive;
using namespace codrive::pdo;

constexpr NodeId kNodes = 16;

/// A bus that only counts: the figure measures the engine, not a socket.
class NullBus final : public ICanBus {
public:
    VoidResult send(const Frame& f) override {
        ++sent;
        checksum += f.data[0];
        return {};
    }
    void set_frame_handler(FrameHandler) override {}
    void set_event_handler(EventHandler) override {}
    [[nodiscard]] std::size_t tx_pending() const override { return 0; }
    [[nodiscard]] const BusStats& stats() const override { return stats_; }
    [[nodiscard]] const std::string& name() const override { return name_; }
    std::uint64_t sent = 0;
    std::uint64_t checksum = 0;

private:
    BusStats stats_;
    std::string name_ = "null";
};

std::vector<Frame> tpdo_frames() {
    std::vector<Frame> frames;
    for (NodeId n = 1; n <= kNodes; ++n) {
        frames.push_back(Frame::make(cob::tpdo(1, n), {0x37, 0x06, n, 0, 0, 0}));
        frames.push_back(Frame::make(cob::tpdo(2, n), {n, 1, 0, 0, 8}));
    }
    return frames;
}

struct EngineSlots {
    ProcessImage* image;
    Slot cw, target, velocity, mode, status, position, actual_velocity, mode_display;
};

std::int64_t run_engine(std::uint64_t cycles) {
    NullBus bus;
    PdoMaster master(bus);
    std::vector<EngineSlots> nodes;
    for (NodeId n = 1; n <= kNodes; ++n) {
        ProcessImage* img = *master.add_node(n, {rpdo(1, {{0x6040, 0, 16}, {0x607A, 0, 32}}, 1),
                                                 rpdo(2, {{0x60FF, 0, 32}, {0x6060, 0, 8}}, 1),
                                                 tpdo(1, {{0x6041, 0, 16}, {0x6064, 0, 32}}, 1),
                                                 tpdo(2, {{0x606C, 0, 32}, {0x6061, 0, 8}}, 1)});
        nodes.push_back({img, *img->slot(0x6040, 0), *img->slot(0x607A, 0), *img->slot(0x60FF, 0),
                         *img->slot(0x6060, 0), *img->slot(0x6041, 0), *img->slot(0x6064, 0),
                         *img->slot(0x606C, 0), *img->slot(0x6061, 0)});
    }
    const std::vector<Frame> rx = tpdo_frames();
    TimePoint now = TimePoint{} + std::chrono::hours(1);
    std::int64_t sum = 0;
    g_counting = true;
    for (std::uint64_t k = 0; k < cycles; ++k) {
        for (auto& s : nodes) { // encode: the application writes its outputs
            s.image->set<std::uint16_t>(s.cw, 0x000F);
            s.image->set<std::int32_t>(s.target, static_cast<std::int32_t>(k));
            s.image->set<std::int32_t>(s.velocity, static_cast<std::int32_t>(k >> 2));
            s.image->set<std::int8_t>(s.mode, 8);
        }
        master.on_sync(k, now);     // send the 32 RPDOs
        for (const Frame& f : rx) { // receive the 32 TPDOs
            master.on_frame(f, now);
        }
        for (auto& s : nodes) { // decode: the application reads its inputs
            sum += s.image->get<std::uint16_t>(s.status);
            sum += s.image->get<std::int32_t>(s.position);
            sum += s.image->get<std::int32_t>(s.actual_velocity);
            sum += s.image->get<std::int8_t>(s.mode_display);
        }
        now += std::chrono::milliseconds(1);
    }
    g_counting = false;
    return sum + static_cast<std::int64_t>(bus.sent);
}

/// The floor: the same bytes copied by hand into frames, the same virtual send, the same bytes
/// copied out of the received frames.
std::int64_t run_floor(std::uint64_t cycles) {
    NullBus bus;
    // Through a pointer the compiler cannot see through, so the send stays a virtual call as
    // in the engine (otherwise it is inlined and the floor is not the same work).
    ICanBus* volatile bus_ptr = &bus;
    ICanBus& ibus = *bus_ptr;
    struct Out {
        std::uint16_t cw;
        std::int32_t target, velocity;
        std::int8_t mode;
    };
    struct In {
        std::uint16_t status;
        std::int32_t position, velocity;
        std::int8_t mode;
    };
    std::vector<Out> outs(kNodes);
    std::vector<In> ins(kNodes);
    const std::vector<Frame> rx = tpdo_frames();
    std::int64_t sum = 0;
    g_counting = true;
    for (std::uint64_t k = 0; k < cycles; ++k) {
        for (auto& o : outs) {
            o.cw = 0x000F;
            o.target = static_cast<std::int32_t>(k);
            o.velocity = static_cast<std::int32_t>(k >> 2);
            o.mode = 8;
        }
        for (NodeId n = 1; n <= kNodes; ++n) {
            const Out& o = outs[n - 1];
            Frame a;
            a.id = cob::rpdo(1, n);
            a.len = 6;
            std::memcpy(a.data.data(), &o.cw, 2);
            std::memcpy(a.data.data() + 2, &o.target, 4);
            ibus.send(a);
            Frame b;
            b.id = cob::rpdo(2, n);
            b.len = 5;
            std::memcpy(b.data.data(), &o.velocity, 4);
            std::memcpy(b.data.data() + 4, &o.mode, 1);
            ibus.send(b);
        }
        for (std::size_t i = 0; i < rx.size(); i += 2) {
            In& in = ins[i / 2];
            std::memcpy(&in.status, rx[i].data.data(), 2);
            std::memcpy(&in.position, rx[i].data.data() + 2, 4);
            std::memcpy(&in.velocity, rx[i + 1].data.data(), 4);
            std::memcpy(&in.mode, rx[i + 1].data.data() + 4, 1);
        }
        for (const auto& in : ins) {
            sum += in.status + in.position + in.velocity + in.mode;
        }
    }
    g_counting = false;
    return sum + static_cast<std::int64_t>(bus.sent);
}

} // namespace

int main(int argc, char** argv) {
    // Usage: bench_pdo_cycle [engine|floor|both] [cycles]
    const std::string which = argc > 1 ? argv[1] : "both";
    const std::uint64_t cycles = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 100000;
    int rc = 0;
    auto report = [&](const char* name, auto fn) {
        const std::uint64_t before = g_allocations.load();
        const auto t0 = std::chrono::steady_clock::now();
        const std::int64_t sum = fn(cycles);
        const auto t1 = std::chrono::steady_clock::now();
        const std::uint64_t allocs = g_allocations.load() - before;
        const double ns = cycles == 0 ? 0.0
                                      : std::chrono::duration<double, std::nano>(t1 - t0).count() /
                                            static_cast<double>(cycles);
        fmt::print("{:<7} {} cycles of 16 nodes x (2 RPDO + 2 TPDO): {:.0f} ns/cycle, "
                   "{} allocations in the cycle loop (checksum {})\n",
                   name, cycles, ns, allocs, sum);
        if (allocs != 0) {
            rc = 1;
        }
    };
    if (which == "engine" || which == "both") {
        report("engine", run_engine);
    }
    if (which == "floor" || which == "both") {
        report("floor", run_floor);
    }
    return rc;
}
