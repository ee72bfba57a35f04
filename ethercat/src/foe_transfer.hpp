// SPDX-License-Identifier: Apache-2.0
// FoE read and write as mailbox step machines (ETG.1000.6 §5.7) for the master's channels.
#pragma once

#include "coe_transfer.hpp"

#include <codrive/ethercat/foe.hpp>

#include <codrive/core/time.hpp>

#include <memory>
#include <string>
#include <vector>

namespace codrive::ethercat::detail {

/// `mailbox_in`: the slave's SM1 size (a DATA with fewer bytes than it allows ends a read);
/// `clock` times BUSY answers against options.busy_timeout.
std::unique_ptr<CoeTransfer> make_foe_read(std::string name, FoeOptions options,
                                           std::size_t mailbox_in, IClock& clock);
/// `mailbox_out`: the slave's SM0 size (bounds each DATA).
std::unique_ptr<CoeTransfer> make_foe_write(std::string name, std::vector<std::uint8_t> data,
                                            FoeOptions options, std::size_t mailbox_out,
                                            IClock& clock);

} // namespace codrive::ethercat::detail
