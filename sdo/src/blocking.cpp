// SPDX-License-Identifier: Apache-2.0
// BlockingSdo: the SDO client driven by its own event loop until each transfer ends.
#include <codrive/sdo/blocking.hpp>

namespace codrive::sdo {

Result<std::unique_ptr<BlockingSdo>> BlockingSdo::open(const std::string& ifname,
                                                       ClientConfig defaults) {
    auto loop = EventLoop::create();
    if (!loop) {
        return fail(loop.error());
    }
    SocketCanOptions options;
    // Only SDO responses (580h..5FFh) and boot-up / heartbeat (700h..77Fh) concern the client.
    options.filters = {CanFilter{cob::kSdoTx, 0x780, false, false},
                       CanFilter{cob::kHeartbeat, 0x780, false, false}};
    options.error_frames = false;
    auto bus = SocketCanBus::open(ifname, options);
    if (!bus) {
        return fail(bus.error());
    }
    std::unique_ptr<BlockingSdo> self(new BlockingSdo());
    self->loop_ = std::move(*loop);
    self->bus_ = std::move(*bus);
    if (auto ok = self->bus_->attach(*self->loop_); !ok) {
        return fail(ok.error());
    }
    self->manager_ =
        std::make_unique<SdoClientManager>(*self->bus_, RealClock::instance(), defaults);
    SdoClientManager* manager = self->manager_.get();
    self->bus_->set_frame_handler(
        [manager](const Frame& f, TimePoint t) { (void)manager->on_frame(f, t); });
    self->loop_->add_timed(manager);
    return self;
}

BlockingSdo::~BlockingSdo() {
    if (loop_ && manager_) {
        loop_->remove_timed(manager_.get());
    }
    if (bus_) {
        bus_->detach();
    }
}

void BlockingSdo::wait(const std::function<bool()>& done) {
    // The client always ends a transfer (timeouts are per request), so no outer limit is needed;
    // the day-long bound only guards against a stalled loop.
    bool cancelled = false;
    const auto interrupted = [&] {
        return !cancelled && interrupt_ ? interrupt_() : std::optional<std::string>();
    };
    while (!done()) {
        if (loop_->run_until([&] { return done() || interrupted().has_value(); },
                             std::chrono::hours(24)) &&
            done()) {
            break;
        }
        if (const auto why = interrupted()) {
            cancelled = true;
            manager_->cancel_all(*why); // each callback runs now, with SdoErrc::Cancelled
            // The abort leaves before the caller (typically a process about to exit) goes on.
            (void)bus_->drain(std::chrono::milliseconds(100));
        }
    }
}

SdoResult<Bytes> BlockingSdo::upload(NodeId node, std::uint16_t index, std::uint8_t subindex,
                                     TransferOptions options) {
    std::optional<SdoResult<Bytes>> out;
    manager_->client(node).upload(
        index, subindex, [&out](SdoResult<Bytes> r) { out = std::move(r); }, std::move(options));
    wait([&out] { return out.has_value(); });
    return std::move(*out);
}

SdoResult<void> BlockingSdo::upload(NodeId node, std::uint16_t index, std::uint8_t subindex,
                                    UploadSink sink, TransferOptions options) {
    std::optional<SdoResult<void>> out;
    manager_->client(node).upload(
        index, subindex, std::move(sink), [&out](SdoResult<void> r) { out = std::move(r); },
        std::move(options));
    wait([&out] { return out.has_value(); });
    return std::move(*out);
}

SdoResult<void> BlockingSdo::download(NodeId node, std::uint16_t index, std::uint8_t subindex,
                                      Bytes data, TransferOptions options) {
    return download(node, index, subindex, bytes_source(std::move(data)), std::move(options));
}

SdoResult<void> BlockingSdo::download(NodeId node, std::uint16_t index, std::uint8_t subindex,
                                      DownloadSource source, TransferOptions options) {
    std::optional<SdoResult<void>> out;
    manager_->client(node).download(
        index, subindex, std::move(source), [&out](SdoResult<void> r) { out = std::move(r); },
        std::move(options));
    wait([&out] { return out.has_value(); });
    return std::move(*out);
}

} // namespace codrive::sdo
