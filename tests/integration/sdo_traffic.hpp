// SPDX-License-Identifier: Apache-2.0
// Continuous SDO traffic to one node for fault-injection runs: chained uploads of reference
// objects and downloads to the scratch object in every mode and size, each result checked.
#pragma once

#include "mini_device.hpp"

#include <codrive/sdo/client.hpp>

#include <fmt/format.h>

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace codrive::integration {

/// Outcome counters shared by every node's traffic.
struct TrafficFigures {
    std::uint64_t submitted = 0;
    std::uint64_t callbacks = 0;
    std::uint64_t ok = 0;
    std::uint64_t ok_bytes = 0;
    std::uint64_t failed = 0;
    std::uint64_t wrong_data = 0;       ///< completed with bytes that differ: must stay 0
    std::uint64_t bad_sentences = 0;    ///< failure text not naming node and object: must stay 0
    std::uint64_t double_callbacks = 0; ///< must stay 0
    std::map<std::string, std::uint64_t> ok_by_mode;
    std::map<std::string, std::uint64_t> failed_by_cause;
    std::vector<std::string> sample_failures; ///< a few sentences for the log
};

/// One planned transfer.
struct PlannedTransfer {
    bool upload = true;
    std::size_t size_index = 0; ///< into kReferenceSizes
    sdo::Mode mode = sdo::Mode::Auto;
};

/// Every size in every mode, both directions.
inline std::vector<PlannedTransfer> full_plan() {
    std::vector<PlannedTransfer> plan;
    for (std::size_t k = 0; k < kReferenceSizes.size(); ++k) {
        for (sdo::Mode m : {sdo::Mode::Auto, sdo::Mode::Segmented, sdo::Mode::Block}) {
            plan.push_back({true, k, m});
            plan.push_back({false, k, m});
        }
    }
    return plan;
}

inline std::string mode_name(sdo::Mode m) {
    switch (m) {
    case sdo::Mode::Auto:
        return "auto";
    case sdo::Mode::Segmented:
        return "segmented";
    case sdo::Mode::Block:
        return "block";
    }
    return "?";
}

/// Keeps one transfer in flight to `device` through `client`, walking `plan` round-robin
/// (starting at an offset so nodes differ), until stop() is called.
class SdoTraffic {
public:
    SdoTraffic(sdo::SdoClient& client, MiniDevice& device, std::vector<PlannedTransfer> plan,
               TrafficFigures& figures, std::size_t offset = 0)
        : client_(client), device_(device), plan_(std::move(plan)), figures_(figures),
          next_(offset % plan_.size()) {}

    void start() { submit(); }
    void stop() { stopped_ = true; }
    [[nodiscard]] bool idle() const { return in_flight_ == 0; }
    /// Call once per cycle: a transfer that failed inside the submitting call (the bus refused
    /// the request, e.g. bus-off) is followed by the next one a cycle later, not recursively.
    void poll() {
        if (deferred_ && !stopped_) {
            deferred_ = false;
            submit();
        }
    }

private:
    void submit() {
        if (stopped_) {
            return;
        }
        if (submitting_) {
            deferred_ = true;
            return;
        }
        submitting_ = true;
        const PlannedTransfer t = plan_[next_];
        next_ = (next_ + 1) % plan_.size();
        ++figures_.submitted;
        ++in_flight_;
        const std::uint64_t serial = ++serial_;
        auto fired = std::make_shared<bool>(false);
        sdo::TransferOptions opt;
        opt.mode = t.mode;
        const std::size_t size = kReferenceSizes[t.size_index];
        const std::string mode =
            std::string(t.upload ? "upload " : "download ") + mode_name(t.mode);
        if (t.upload) {
            const auto index = static_cast<std::uint16_t>(kReference + t.size_index);
            client_.upload(
                index, 0,
                [this, fired, size, mode, index](sdo::SdoResult<sdo::Bytes> r) {
                    if (!first_call(*fired)) {
                        return;
                    }
                    if (r) {
                        record_ok(mode, *r == reference_pattern(size), r->size());
                    } else {
                        record_failure(r.error(), index);
                    }
                    done(!r && refused(r.error()));
                },
                opt);
        } else {
            auto data = reference_pattern(size, static_cast<std::uint32_t>(serial));
            client_.download(
                kScratch, 0, data,
                [this, fired, data, mode](sdo::SdoResult<void> r) {
                    if (!first_call(*fired)) {
                        return;
                    }
                    if (r) {
                        // The server stores the value before it confirms (CiA 301 §7.2.4.3.3).
                        record_ok(mode, device_.scratch() == data, data.size());
                    } else {
                        record_failure(r.error(), kScratch);
                    }
                    done(!r && refused(r.error()));
                },
                opt);
        }
        submitting_ = false;
    }

    bool first_call(bool& fired) {
        ++figures_.callbacks;
        if (fired) {
            ++figures_.double_callbacks;
            return false;
        }
        fired = true;
        return true;
    }
    void record_ok(const std::string& mode, bool exact, std::size_t bytes) {
        if (!exact) {
            ++figures_.wrong_data;
            return;
        }
        ++figures_.ok;
        figures_.ok_bytes += bytes;
        ++figures_.ok_by_mode[mode];
    }
    void record_failure(const sdo::SdoError& e, std::uint16_t index) {
        ++figures_.failed;
        const std::string text = e.to_string();
        char node[16];
        char object[16];
        std::snprintf(node, sizeof node, "node %u:", static_cast<unsigned>(device_.node()));
        std::snprintf(object, sizeof object, "0x%04X:00", static_cast<unsigned>(index));
        if (text.rfind(node, 0) != 0 || text.find(object) == std::string::npos) {
            ++figures_.bad_sentences;
        }
        std::string key;
        if (const auto code = e.abort_code()) {
            char buf[48];
            std::snprintf(buf, sizeof buf, "abort 0x%08X by %s", *code,
                          e.origin == sdo::AbortOrigin::Client ? "client" : "server");
            key = buf;
        } else {
            key = e.cause.message();
            if (e.cause == make_error_code(sdo::SdoErrc::Timeout)) {
                // Group timeouts by protocol and phase ("block download: no response to end
                // request"), without the byte counts.
                const std::string phase = e.detail.substr(0, e.detail.find(" after"));
                key += fmt::format(" ({} {}: {})", to_string(e.protocol), to_string(e.direction),
                                   phase);
            }
        }
        if (figures_.failed_by_cause[key]++ == 0 && figures_.sample_failures.size() < 12) {
            figures_.sample_failures.push_back(text);
        }
    }
    /// The bus refused the request (bus-off): like an application's retry policy, wait a cycle
    /// before the next request rather than re-submitting from inside the failing call.
    static bool refused(const sdo::SdoError& e) {
        return e.cause == make_error_code(sdo::SdoErrc::SendFailed);
    }
    void done(bool wait_a_cycle) {
        --in_flight_;
        if (wait_a_cycle) {
            deferred_ = true;
            return;
        }
        submit();
    }

    sdo::SdoClient& client_;
    MiniDevice& device_;
    std::vector<PlannedTransfer> plan_;
    TrafficFigures& figures_;
    std::size_t next_;
    std::uint64_t serial_ = 0;
    int in_flight_ = 0;
    bool stopped_ = false;
    bool submitting_ = false;
    bool deferred_ = false;
};

inline void print_figures(const char* title, const TrafficFigures& f) {
    std::printf("%s\n", title);
    std::printf("  SDO transfers: %llu submitted, %llu ok (%llu bytes), %llu failed, "
                "%llu wrong data, %llu double callbacks, %llu failures without a proper sentence\n",
                static_cast<unsigned long long>(f.submitted), static_cast<unsigned long long>(f.ok),
                static_cast<unsigned long long>(f.ok_bytes),
                static_cast<unsigned long long>(f.failed),
                static_cast<unsigned long long>(f.wrong_data),
                static_cast<unsigned long long>(f.double_callbacks),
                static_cast<unsigned long long>(f.bad_sentences));
    for (const auto& [mode, n] : f.ok_by_mode) {
        std::printf("    ok   %-22s %llu\n", mode.c_str(), static_cast<unsigned long long>(n));
    }
    for (const auto& [cause, n] : f.failed_by_cause) {
        std::printf("    fail %-40s %llu\n", cause.c_str(), static_cast<unsigned long long>(n));
    }
    for (const auto& s : f.sample_failures) {
        std::printf("    e.g. %s\n", s.c_str());
    }
}

} // namespace codrive::integration
