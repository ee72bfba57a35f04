// SPDX-License-Identifier: Apache-2.0
// Master FoE API: file reads and writes queued on the slave's mailbox channel (ETG.1000.6 §5.7).
#include "foe_transfer.hpp"

#include <codrive/ethercat/master.hpp>

namespace codrive::ethercat {

VoidResult Master::foe_read_async(std::size_t slave, std::string name, CoeDone done,
                                  FoeOptions options) {
    const std::size_t mbx = slave < slaves_.size() ? slaves_[slave].sii.tx_mailbox_size : 0;
    auto t = detail::make_foe_read(std::move(name), std::move(options), mbx, clock_);
    t->done = std::move(done);
    return submit(slave, std::move(t));
}

VoidResult Master::foe_write_async(std::size_t slave, std::string name,
                                   std::vector<std::uint8_t> data, CoeDone done,
                                   FoeOptions options) {
    const std::size_t mbx = slave < slaves_.size() ? slaves_[slave].sii.rx_mailbox_size : 0;
    auto t =
        detail::make_foe_write(std::move(name), std::move(data), std::move(options), mbx, clock_);
    t->done = std::move(done);
    return submit(slave, std::move(t));
}

Result<std::vector<std::uint8_t>> Master::foe_read(std::size_t slave, const std::string& name,
                                                   FoeOptions options) {
    const std::size_t mbx = slave < slaves_.size() ? slaves_[slave].sii.tx_mailbox_size : 0;
    return run_transfer(slave, detail::make_foe_read(name, std::move(options), mbx, clock_));
}

VoidResult Master::foe_write(std::size_t slave, const std::string& name,
                             std::span<const std::uint8_t> data, FoeOptions options) {
    const std::size_t mbx = slave < slaves_.size() ? slaves_[slave].sii.rx_mailbox_size : 0;
    auto r = run_transfer(
        slave, detail::make_foe_write(name, std::vector<std::uint8_t>(data.begin(), data.end()),
                                      std::move(options), mbx, clock_));
    if (!r) {
        return fail(r.error());
    }
    return {};
}

} // namespace codrive::ethercat
