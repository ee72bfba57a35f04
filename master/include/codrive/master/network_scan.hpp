// SPDX-License-Identifier: Apache-2.0
// Finds the nodes on a bus: probes 1000h of nodes 1..127 in parallel, then, once every probe has
// ended, reads identity and name of those that answered.
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/time.hpp>
#include <codrive/nmt/state.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace codrive::sdo {
class SdoClientManager;
}
namespace codrive::nmt {
class NodeStateTable;
}

namespace codrive::master {

struct ScanRow {
    NodeId node = 0;
    nmt::NmtState state = nmt::NmtState::Unknown; ///< from heartbeats heard during the scan
    std::uint32_t device_type = 0;
    std::optional<std::uint32_t> vendor_id;
    std::optional<std::uint32_t> product_code;
    std::optional<std::uint32_t> revision;
    std::optional<std::uint32_t> serial;
    std::string name; ///< 1008h, "" if the node has none
};

struct ScanOptions {
    NodeId first = 1;
    NodeId last = kMaxNodeId;
    milliseconds timeout{300}; ///< per SDO request
    /// Repeats of an identity or name read that timed out (the 1000h probe is never repeated: an
    /// absent node must not cost more than one timeout). A node that answered 1000h exists, so
    /// a lost 1018h/1008h answer is worth asking again.
    int detail_retries = 2;
};

/// Runs one scan. The SDO clients of the probed nodes get the scan's timeout for its requests.
class NetworkScan {
public:
    using Done = std::function<void(std::vector<ScanRow>)>;
    NetworkScan(sdo::SdoClientManager& sdo, const nmt::NodeStateTable* states,
                ScanOptions options = {});
    ~NetworkScan();
    void start(Done done);
    [[nodiscard]] bool finished() const { return left_ == 0; }

private:
    void probe_done();
    void probe_details(std::size_t row);
    void node_done();
    void node_done_all();

    sdo::SdoClientManager& sdo_;
    const nmt::NodeStateTable* states_;
    ScanOptions options_;
    std::vector<ScanRow> rows_;
    std::size_t probes_left_ = 0; ///< 1000h probes still running (first phase)
    std::size_t left_ = 0;        ///< probes plus found nodes whose details are still being read
    Done done_;
    std::shared_ptr<bool> alive_;
};

/// An aligned table: node, state, device type, vendor, product, revision, serial, name.
[[nodiscard]] std::string format_scan_table(const std::vector<ScanRow>& rows);

} // namespace codrive::master
