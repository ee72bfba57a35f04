// SPDX-License-Identifier: Apache-2.0
// Blocking SDO access for scripts and tools: runs an EventLoop + SocketCanBus per call.
#pragma once

#include <codrive/core/event_loop.hpp>
#include <codrive/core/socket_can_bus.hpp>
#include <codrive/sdo/client_manager.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace codrive::sdo {

/// Owns an event loop, a SocketCAN bus and SDO clients for every node; each call runs the loop
/// until its transfer ends (success, abort or timeout — the client guarantees one of them).
/// Not for the real-time thread; one thread at a time.
class BlockingSdo {
public:
    /// Opens `ifname`. Errors: those of EventLoop::create and SocketCanBus::open (NoSocketCan,
    /// NoSuchInterface, system errors).
    static Result<std::unique_ptr<BlockingSdo>> open(const std::string& ifname,
                                                     ClientConfig defaults = {});
    ~BlockingSdo();
    BlockingSdo(const BlockingSdo&) = delete;
    BlockingSdo& operator=(const BlockingSdo&) = delete;

    SdoResult<Bytes> upload(NodeId node, std::uint16_t index, std::uint8_t subindex,
                            TransferOptions options = {});
    SdoResult<void> upload(NodeId node, std::uint16_t index, std::uint8_t subindex, UploadSink sink,
                           TransferOptions options = {});
    SdoResult<void> download(NodeId node, std::uint16_t index, std::uint8_t subindex, Bytes data,
                             TransferOptions options = {});
    SdoResult<void> download(NodeId node, std::uint16_t index, std::uint8_t subindex,
                             DownloadSource source, TransferOptions options = {});

    /// Typed read/write, as SdoClient::read/write.
    template <typename T>
    SdoResult<T> read(NodeId node, std::uint16_t index, std::uint8_t subindex,
                      TransferOptions options = {}) {
        std::optional<SdoResult<T>> out;
        manager_->client(node).read<T>(
            index, subindex, [&out](SdoResult<T> r) { out = std::move(r); }, std::move(options));
        wait([&out] { return out.has_value(); });
        return std::move(*out);
    }
    template <typename T>
    SdoResult<void> write(NodeId node, std::uint16_t index, std::uint8_t subindex, const T& value,
                          TransferOptions options = {}) {
        std::optional<SdoResult<void>> out;
        manager_->client(node).write<T>(
            index, subindex, value, [&out](SdoResult<void> r) { out = std::move(r); },
            std::move(options));
        wait([&out] { return out.has_value(); });
        return std::move(*out);
    }

    [[nodiscard]] SdoClientManager& manager() { return *manager_; }
    [[nodiscard]] EventLoop& loop() { return *loop_; }
    [[nodiscard]] SocketCanBus& bus() { return *bus_; }

    /// Asked while a call waits (after each frame, at least every 50 ms): once it returns a
    /// reason (e.g. "interrupted by SIGINT"), the call's transfer ends at once: the node gets
    /// abort 0x08000000 (CiA 301 §7.2.4.3.17: general error), which ends its side of a
    /// segmented or block transfer instead of leaving it to its timeout, and the call returns
    /// SdoErrc::Cancelled with the reason as its detail. Empty: calls wait until their
    /// transfer ends by itself.
    using Interrupt = std::function<std::optional<std::string>()>;
    void set_interrupt(Interrupt interrupt) { interrupt_ = std::move(interrupt); }

private:
    BlockingSdo() = default;
    void wait(const std::function<bool()>& done);

    std::unique_ptr<EventLoop> loop_;
    std::unique_ptr<SocketCanBus> bus_;
    std::unique_ptr<SdoClientManager> manager_;
    Interrupt interrupt_;
};

} // namespace codrive::sdo
