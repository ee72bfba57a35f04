// SPDX-License-Identifier: Apache-2.0
// The slave side of CoE: SDO server (expedited, normal, segmented, complete access), SDO
// information service and emergency messages over an ObjectDictionary (ETG.1000.6 §5.6.2).
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/emcy/message.hpp>
#include <codrive/ethercat/al_state.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace codrive::sim::ecat {

class CoeServer {
public:
    /// `mailbox_size`: the slave's SM1 size (bounds every answer).
    CoeServer(ObjectDictionary& od, std::size_t mailbox_size);

    /// Handles one CoE payload (CoE header first) and returns the CoE answers (zero for an
    /// abort request from the master, several for a fragmented SDO information answer).
    std::vector<std::vector<std::uint8_t>> handle(std::span<const std::uint8_t> payload,
                                                  ethercat::AlState state);
    /// The CoE payload of an emergency message.
    [[nodiscard]] static std::vector<std::uint8_t> emergency(const emcy::EmcyMessage& m);

    /// Objects that may be written only in PRE-OP (PDO assignment and mapping, ETG.1000.6
    /// §5.6.7.4); writes in SAFE-OP/OP abort 0x08000022.
    [[nodiscard]] static bool preop_only(std::uint16_t index);

private:
    std::vector<std::uint8_t> sdo(std::span<const std::uint8_t> p, ethercat::AlState state);
    std::vector<std::vector<std::uint8_t>> info(std::span<const std::uint8_t> p);
    std::vector<std::uint8_t> abort(std::uint16_t index, std::uint8_t sub, std::uint32_t code);
    tl::expected<std::vector<std::uint8_t>, SdoAbort> read_value(std::uint16_t index,
                                                                 std::uint8_t sub, bool ca);
    tl::expected<void, SdoAbort> write_value(std::uint16_t index, std::uint8_t sub,
                                             std::span<const std::uint8_t> data, bool ca,
                                             ethercat::AlState state);

    ObjectDictionary& od_;
    std::size_t mailbox_size_;
    // Segmented transfer in progress.
    bool upload_active_ = false;
    bool download_active_ = false;
    std::uint16_t xfer_index_ = 0;
    std::uint8_t xfer_sub_ = 0;
    bool xfer_ca_ = false;
    std::uint8_t toggle_ = 0;
    std::vector<std::uint8_t> buffer_;
    std::size_t offset_ = 0;
    std::uint32_t expected_size_ = 0;
};

} // namespace codrive::sim::ecat
