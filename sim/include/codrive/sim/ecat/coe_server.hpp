// SPDX-License-Identifier: Apache-2.0
// The slave side of CoE: SDO requests served by the SDO server machine of sdo/ with CoE's framing
// (expedited, normal, segmented, complete access), the SDO information service and emergency
// messages over an ObjectDictionary (ETG.1000.6 §5.6.2-3).
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/emcy/message.hpp>
#include <codrive/ethercat/al_state.hpp>
#include <codrive/sdo/server_machine.hpp>

#include <cstdint>
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

    /// The SDO server (its statistics, for tests).
    [[nodiscard]] const sdo::SdoServerMachine& sdo_server() const { return sdo_; }

private:
    std::vector<std::vector<std::uint8_t>> info(std::span<const std::uint8_t> p);

    ObjectDictionary& od_;
    std::size_t mailbox_size_;
    ethercat::AlState state_ = ethercat::AlState::Init;
    std::vector<std::vector<std::uint8_t>> sdo_replies_; ///< what the machine sent for a request
    sdo::SdoServerMachine sdo_;
};

} // namespace codrive::sim::ecat
