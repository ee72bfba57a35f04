// SPDX-License-Identifier: Apache-2.0
// The real link: an AF_PACKET raw socket bound to one interface, ethertype 88A4h only.
#pragma once

#include <codrive/ethercat/link.hpp>

#include <functional>
#include <memory>

namespace codrive::ethercat {

/// A raw Ethernet socket for EtherCAT frames. Outgoing frames are not looped back to it
/// (PACKET_IGNORE_OUTGOING), so a master only sees the frames the segment returns.
class RawSocketLink final : public IEcatLink {
public:
    /// Opens and binds the socket. Errors: PermissionDenied without CAP_NET_RAW,
    /// CoreErrc::NoSuchInterface, CoreErrc::InterfaceDown, other errno values.
    static Result<std::unique_ptr<RawSocketLink>> open(const std::string& ifname);
    ~RawSocketLink() override;
    RawSocketLink(const RawSocketLink&) = delete;
    RawSocketLink& operator=(const RawSocketLink&) = delete;

    VoidResult send(std::span<const std::uint8_t> frame) override;
    Result<std::size_t> receive(std::span<std::uint8_t> buffer, TimePoint deadline) override;
    void idle(Duration d) override;
    [[nodiscard]] std::string name() const override { return ifname_; }
    [[nodiscard]] int fd() const { return fd_; }

    /// Called with every frame sent (outgoing = true) and received, e.g. to write a pcap.
    using Tap = std::function<void(std::span<const std::uint8_t> frame, bool outgoing)>;
    void set_tap(Tap tap) { tap_ = std::move(tap); }

    /// The message for an open() error naming the interface: "cannot open a raw EtherCAT socket
    /// on veth0: ... needs CAP_NET_RAW ...".
    [[nodiscard]] static std::string describe_open_error(const std::string& ifname,
                                                         const std::error_code& ec);

private:
    RawSocketLink(int fd, std::string ifname) : fd_(fd), ifname_(std::move(ifname)) {}
    /// The interface's IFF_UP flag (SIOCGIFFLAGS); false if it cannot be read.
    [[nodiscard]] bool interface_up() const;
    int fd_ = -1;
    std::string ifname_;
    Tap tap_;
};

} // namespace codrive::ethercat
