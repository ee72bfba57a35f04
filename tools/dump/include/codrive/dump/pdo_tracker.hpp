// SPDX-License-Identifier: Apache-2.0
// PDO communication and mapping parameters learned from SDO traffic or EDS/DCF files, and PDO
// frames decoded with them into named, typed values (CiA 301 §7.2.2, §7.5.2.35-38).
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/core/eds.hpp>
#include <codrive/dump/object_catalog.hpp>

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace codrive::dump {

/// Knows which COB-ID carries which PDO of which node and what it maps.
class PdoTracker {
public:
    explicit PdoTracker(const ObjectCatalog& catalog);

    /// Learns from a completed SDO transfer of node `node` (download or upload) of an object in
    /// 1400h..1BFFh; other objects are ignored. Returns true if it changed a PDO.
    bool learn(NodeId node, std::uint16_t index, std::uint8_t subindex,
               std::span<const std::uint8_t> data);
    /// Loads the PDO parameters an EDS/DCF gives for `node` (what the node uses after boot).
    void learn_from_description(NodeId node, const DeviceDescription& desc);

    /// Decodes a PDO frame if its COB-ID belongs to a known or default PDO; appends
    /// "node 4 TPDO1 Statusword=0x0637 (OPERATION ENABLED), Position actual value=1200" and
    /// returns the node, or returns 0 and appends nothing if the id is no PDO.
    NodeId decode(std::uint32_t cob_id, std::span<const std::uint8_t> payload,
                  fmt::memory_buffer& out);
    /// For a remote frame on a known or default PDO's COB-ID: appends "node 3 TPDO1 remote
    /// request" and returns the node; else 0 and nothing.
    NodeId remote_request(std::uint32_t cob_id, fmt::memory_buffer& out);

private:
    struct Entry {
        std::uint16_t index = 0;
        std::uint8_t subindex = 0;
        std::uint8_t bits = 0;
        bool is_signed = false;
        bool is_real = false;
        bool hex = false;
        bool dummy = false;
        bool string = false;
        std::string name;
    };
    struct Pdo {
        NodeId node = 0;
        bool tpdo = false;
        std::uint16_t number = 0; ///< 1..512
        std::uint32_t cob_id = 0; ///< 11-bit id in use, 0 if none
        bool valid = true;
        bool map_known = false;
        bool dirty = true;
        std::uint8_t count = 0;
        std::array<std::uint32_t, 64> raw{};
        std::vector<Entry> entries;
        std::string label; ///< "TPDO1"
    };
    static constexpr std::uint32_t kNoPdo = 0xFFFFFFFF;

    Pdo& pdo(NodeId node, bool tpdo, std::uint16_t number);
    /// The PDO that uses `cob_id` now (a default one created on first use), or null.
    Pdo* find(std::uint32_t cob_id);
    void set_cob_id(Pdo& p, std::uint32_t cob_value);
    void resolve(Pdo& p);

    const ObjectCatalog& catalog_;
    std::unordered_map<std::uint32_t, Pdo> pdos_; ///< key: node << 16 | tpdo << 15 | number
    std::array<std::uint32_t, 2048> by_cob_{};    ///< 11-bit COB-ID → key
};

} // namespace codrive::dump
