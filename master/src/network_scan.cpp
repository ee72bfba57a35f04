// SPDX-License-Identifier: Apache-2.0
// Parallel node discovery over SDO (every node's client runs concurrently).
#include <codrive/master/network_scan.hpp>

#include <codrive/nmt/node_state_table.hpp>
#include <codrive/sdo/client_manager.hpp>

#include <algorithm>
#include <fmt/format.h>

namespace codrive::master {

NetworkScan::NetworkScan(sdo::SdoClientManager& sdo, const nmt::NodeStateTable* states,
                         ScanOptions options)
    : sdo_(sdo), states_(states), options_(options), alive_(std::make_shared<bool>(true)) {}

NetworkScan::~NetworkScan() {
    *alive_ = false;
}

void NetworkScan::start(Done done) {
    done_ = std::move(done);
    rows_.clear();
    const unsigned first = std::max<unsigned>(1, options_.first);
    const unsigned last = std::min<unsigned>(kMaxNodeId, options_.last);
    probes_left_ = last >= first ? last - first + 1 : 0;
    left_ = probes_left_;
    if (left_ == 0) {
        if (done_) {
            done_({});
        }
        return;
    }
    rows_.reserve(left_);
    for (unsigned n = first; n <= last; ++n) {
        sdo::TransferOptions o;
        o.timeout = options_.timeout;
        o.retries = 0;
        const auto node = static_cast<NodeId>(n);
        sdo_.client(node).read<std::uint32_t>(
            0x1000, 0,
            [this, alive = alive_, node](sdo::SdoResult<std::uint32_t> r) {
                if (!*alive) {
                    return;
                }
                // A node that aborts the read exists all the same (1000h is mandatory, but a
                // broken node should still be listed).
                if (r || (r.error().abort_code() && r.error().origin == sdo::AbortOrigin::Server)) {
                    ScanRow row;
                    row.node = node;
                    row.device_type = r ? *r : 0;
                    rows_.push_back(row);
                }
                probe_done();
            },
            o);
    }
}

void NetworkScan::probe_done() {
    if (probes_left_ == 0 || --probes_left_ > 0) {
        return;
    }
    // The details are read only once every probe has ended. Found early, a node's 1018h request
    // would queue behind the probes (and the timeout aborts) of up to 126 absent nodes still
    // waiting in the transmit queue, and its timeout runs from the moment it is queued: on a
    // slow bus (or a loaded vcan, where CANopenNode's demo device answered in 1 ms) the answer
    // came after the client had given up and the scan showed its vendor-ID as "-".
    left_ = rows_.size();
    if (left_ == 0) {
        node_done_all();
        return;
    }
    // probe_details() may finish a node synchronously (a send refused at once): iterate over a
    // count fixed now.
    for (std::size_t i = 0; i < rows_.size(); ++i) {
        probe_details(i);
    }
}

void NetworkScan::probe_details(std::size_t row) {
    const NodeId node = rows_[row].node;
    auto& client = sdo_.client(node);
    sdo::TransferOptions o;
    o.timeout = options_.timeout;
    o.retries = options_.detail_retries;
    for (std::uint8_t sub = 1; sub <= 4; ++sub) {
        client.read<std::uint32_t>(
            0x1018, sub,
            [this, alive = alive_, row, sub](sdo::SdoResult<std::uint32_t> r) {
                if (!*alive || !r) {
                    return;
                }
                ScanRow& s = rows_[row];
                (sub == 1   ? s.vendor_id
                 : sub == 2 ? s.product_code
                 : sub == 3 ? s.revision
                            : s.serial) = *r;
            },
            o);
    }
    // Requests run in order per node, so the name read ends this node's scan.
    client.read<std::string>(
        0x1008, 0,
        [this, alive = alive_, row](sdo::SdoResult<std::string> r) {
            if (!*alive) {
                return;
            }
            if (r) {
                rows_[row].name = *r;
            }
            node_done();
        },
        o);
}

void NetworkScan::node_done() {
    if (left_ == 0) {
        return;
    }
    if (--left_ == 0) {
        node_done_all();
    }
}

void NetworkScan::node_done_all() {
    std::sort(rows_.begin(), rows_.end(),
              [](const ScanRow& a, const ScanRow& b) { return a.node < b.node; });
    if (states_ != nullptr) {
        for (auto& r : rows_) {
            // A node whose last message was its boot-up is pre-operational (CiA 301
            // §7.3.2.1: initialisation ends in pre-operational on its own).
            const nmt::NmtState s = states_->state(r.node);
            r.state = s == nmt::NmtState::BootUp ? nmt::NmtState::PreOperational : s;
        }
    }
    if (done_) {
        done_(rows_);
    }
}

std::string format_scan_table(const std::vector<ScanRow>& rows) {
    auto hex = [](const std::optional<std::uint32_t>& v) {
        return v ? fmt::format("0x{:08X}", *v) : std::string("-");
    };
    std::string out =
        fmt::format("{:>4}  {:<15}  {:<10}  {:<10}  {:<10}  {:<10}  {:<10}  {}\n", "node", "state",
                    "device", "vendor", "product", "revision", "serial", "name");
    for (const auto& r : rows) {
        out += fmt::format("{:>4}  {:<15}  0x{:08X}  {:<10}  {:<10}  {:<10}  {:<10}  {}\n", r.node,
                           nmt::to_string(r.state), r.device_type, hex(r.vendor_id),
                           hex(r.product_code), hex(r.revision), hex(r.serial), r.name);
    }
    out += fmt::format("{} node{} found\n", rows.size(), rows.size() == 1 ? "" : "s");
    return out;
}

} // namespace codrive::master
