// SPDX-License-Identifier: Apache-2.0
// Asynchronous SDO client for one SDO channel (CiA 301 §7.2.4): a sans-I/O state machine with a
// queue, one transfer in flight, per-request timeouts and typed convenience calls.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/cob_id.hpp>
#include <codrive/core/endian.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/frame.hpp>
#include <codrive/sdo/client_machine.hpp>
#include <codrive/sdo/error.hpp>
#include <codrive/sdo/protocol.hpp>
#include <codrive/sdo/transfer.hpp>

#include <concepts>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>

namespace codrive::sdo {

struct ClientConfig {
    NodeId node = 1;
    /// COB-IDs of the channel; 0 = default SDO channel 600h+node (request), 580h+node (response).
    std::uint32_t request_id = 0;
    std::uint32_t response_id = 0;
    Duration timeout = std::chrono::milliseconds(1000);
    int retries = 0;
    /// Block upload: acknowledge early if a sub-block stalls this long (a lost last segment).
    Duration block_gap_timeout = std::chrono::milliseconds(100);
    /// Block upload: send the upload start or a sub-block response again when nothing of the
    /// sub-block arrives within `block_gap_timeout`. Off by default, as on the server
    /// (ServerConfig::repeat_block_responses): CiA 301 §7.2.4.3.14-15 has one response per step,
    /// and a server slower than 100 ms to start its sub-block gets the copy as its next request.
    /// Only for lossy links where the response itself may vanish (fault injection).
    bool repeat_block_responses = false;
    /// End the transfer when the node sends its boot-up message (700h+node, data 00).
    bool watch_boot_up = true;
};

struct ClientStats {
    std::uint64_t completed = 0;
    std::uint64_t failed = 0;
    std::uint64_t frames_ignored = 0;       ///< frames not for this channel
    std::uint64_t unexpected_responses = 0; ///< responses while idle (e.g. late, after timeout)
    /// Responses ignored during a transfer as repeats or leftovers of an earlier transfer or
    /// phase (see docs/sdo.md, "Duplicated, late and reordered responses").
    std::uint64_t stale_responses = 0;
    std::uint64_t retries = 0;
    std::uint64_t retransmitted_segments = 0;
    std::uint64_t early_acks = 0; ///< sub-blocks acknowledged by the gap timer
    /// Block upload start / sub-block responses sent again because no segment followed.
    std::uint64_t acks_repeated = 0;
};

namespace detail {
struct ClientTransfer;
}

template <typename T>
concept SdoScalar = std::is_arithmetic_v<T>;

/// The client of one SDO channel. Requests queue and run one at a time, in order. Completion
/// callbacks run from on_frame()/on_tick() (or from the submitting call if sending fails); a
/// callback may submit further requests. Callbacks never nest: a retry submitted from a
/// callback while every send fails runs after that callback returns, and after 16 such failures
/// in one call the rest waits for the next on_tick().
class SdoClient final : public ITimed {
public:
    SdoClient(ICanBus& bus, const IClock& clock, ClientConfig config);
    ~SdoClient() override; ///< pending callbacks are not called
    SdoClient(const SdoClient&) = delete;
    SdoClient& operator=(const SdoClient&) = delete;

    /// Reads an object into memory. Errors: see SdoError (server abort, timeout, node rebooted,
    /// wrong object, protocol error).
    TransferId upload(std::uint16_t index, std::uint8_t subindex, UploadCallback done,
                      TransferOptions options = {});
    /// Reads an object into a sink (for large domains); the callback only reports the outcome.
    TransferId upload(std::uint16_t index, std::uint8_t subindex, UploadSink sink,
                      DoneCallback done, TransferOptions options = {});
    /// Writes bytes. Errors as upload(), plus TooLarge.
    TransferId download(std::uint16_t index, std::uint8_t subindex, Bytes data, DoneCallback done,
                        TransferOptions options = {});
    /// Writes from a source (for large domains).
    TransferId download(std::uint16_t index, std::uint8_t subindex, DownloadSource source,
                        DoneCallback done, TransferOptions options = {});

    /// Typed read: integers and reals (exact size required, else SizeMismatch), std::string
    /// (visible string, trailing NULs dropped) or Bytes.
    template <typename T>
    TransferId read(std::uint16_t index, std::uint8_t subindex,
                    std::function<void(SdoResult<T>)> done, TransferOptions options = {});
    /// Typed write of a scalar (little-endian, exact size), a string or Bytes.
    template <typename T>
    TransferId write(std::uint16_t index, std::uint8_t subindex, const T& value, DoneCallback done,
                     TransferOptions options = {});

    /// Cancels a queued transfer, or aborts the running one (abort 0x08000000 to the server).
    /// The callback is called with SdoErrc::Cancelled. False if the id is unknown.
    bool cancel(TransferId id);
    /// Ends every transfer at once, the queued ones in order and the running one (abort
    /// 0x08000000 to the server), each callback once with SdoErrc::Cancelled and `why` as the
    /// detail ("node 5: SDO upload 0x1018:01 failed: cancelled (why)"). Transfers a callback
    /// submits meanwhile end the same way (up to 64 of them: what a callback that submits on
    /// every failure queues beyond that starts at the next on_tick()); nothing starts until it
    /// returns. The number ended.
    std::size_t cancel_all(std::string_view why);

    /// Feeds a received frame. True if it belonged to this channel.
    bool on_frame(const Frame& frame, TimePoint now);
    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

    [[nodiscard]] bool busy() const;
    [[nodiscard]] std::size_t queued() const { return queue_.size(); }
    [[nodiscard]] const ClientStats& stats() const { return stats_; }
    [[nodiscard]] const ClientConfig& config() const { return config_; }
    [[nodiscard]] std::uint32_t request_id() const { return request_id_; }
    [[nodiscard]] std::uint32_t response_id() const { return response_id_; }

private:
    using Transfer = detail::ClientTransfer;
    TransferId enqueue(std::unique_ptr<Transfer> t);
    void start_next(TimePoint now);
    void start(Transfer& t, TimePoint now);
    bool send(const std::array<std::uint8_t, 8>& payload);
    void finish(SdoResult<void> outcome);
    void fail(std::error_code cause, std::string detail, AbortOrigin origin = AbortOrigin::None);
    /// The running transfer ends: abort 0x08000000 to the server, callback with Cancelled.
    void cancel_running(std::string detail);
    /// A queued transfer that never started ends: its callback with `cause` and `detail`.
    void end_queued(std::unique_ptr<Transfer> t, std::error_code cause, std::string detail);
    void abort_and_fail(std::uint32_t code, std::string detail);
    void arm(TimePoint now);
    void reschedule();
    void handle_response(const Frame& frame, TimePoint now);
    void remember_response(const Frame& frame);
    [[nodiscard]] bool is_repeat(const Frame& frame) const;
    [[nodiscard]] bool is_leftover(const FrameInfo& info);
    void server_abort(const FrameInfo& info);
    /// Segmented or block upload accepted: takes the indicated size (reserving the buffer) and
    /// opens the sink; false when the sink refused and the transfer was aborted.
    [[nodiscard]] bool begin_upload_data(const FrameInfo& info);
    void handle_block_upload_segment(const Frame& frame, TimePoint now);
    void on_timeout(TimePoint now);
    bool deliver(std::span<const std::uint8_t> data);
    bool read_source(std::span<std::uint8_t> out);
    void sync(Transfer& t);
    void apply(SdoClientMachine::Step step, TimePoint now);
    void fail_with(const SdoClientMachine::Failure& f);
    void send_sub_block(TimePoint now);
    void send_block_upload_ack(TimePoint now, bool early = false);
    void report_progress();
    [[nodiscard]] SdoError make_error(const Transfer& t, std::error_code cause, std::string detail,
                                      AbortOrigin origin) const;

    ICanBus& bus_;
    const IClock& clock_;
    ClientConfig config_;
    std::uint32_t request_id_;
    std::uint32_t response_id_;
    std::deque<std::unique_ptr<Transfer>> queue_;
    std::unique_ptr<Transfer> active_;
    TransferId next_id_ = 1;
    TimePoint deadline_ = kNever;
    TimePoint dispatch_now_ = kNever; ///< time of the frame/tick being handled
    ClientStats stats_;
    bool in_callback_ = false;
    bool draining_ = false;       ///< start_next() is running (it never nests)
    bool deferred_start_ = false; ///< queued transfers wait for the next on_tick()
};

// ---- typed helpers ---------------------------------------------------------------------------

namespace detail {
[[nodiscard]] SdoError size_mismatch(NodeId node, std::uint16_t index, std::uint8_t subindex,
                                     std::size_t got, std::size_t want);
}

template <typename T>
TransferId SdoClient::read(std::uint16_t index, std::uint8_t subindex,
                           std::function<void(SdoResult<T>)> done, TransferOptions options) {
    const NodeId node = config_.node;
    return upload(
        index, subindex,
        [done = std::move(done), node, index, subindex](SdoResult<Bytes> r) {
            if (!r) {
                done(tl::unexpected(std::move(r.error())));
                return;
            }
            if constexpr (std::is_same_v<T, Bytes>) {
                done(std::move(*r));
            } else if constexpr (std::is_same_v<T, std::string>) {
                std::string s(r->begin(), r->end());
                while (!s.empty() && s.back() == '\0') {
                    s.pop_back();
                }
                done(std::move(s));
            } else {
                static_assert(SdoScalar<T>, "read<T>: T must be arithmetic, std::string or Bytes");
                if (r->size() != sizeof(T)) {
                    done(tl::unexpected(
                        detail::size_mismatch(node, index, subindex, r->size(), sizeof(T))));
                    return;
                }
                done(get_le<T>(r->data()));
            }
        },
        std::move(options));
}

template <typename T>
TransferId SdoClient::write(std::uint16_t index, std::uint8_t subindex, const T& value,
                            DoneCallback done, TransferOptions options) {
    Bytes bytes;
    if constexpr (std::is_same_v<T, Bytes>) {
        bytes = value;
    } else if constexpr (std::is_convertible_v<const T&, std::string_view>) {
        const std::string_view s(value);
        bytes.assign(s.begin(), s.end());
    } else {
        static_assert(SdoScalar<T>, "write<T>: T must be arithmetic, a string or Bytes");
        bytes.resize(sizeof(T));
        put_le<T>(bytes.data(), value);
    }
    return download(index, subindex, std::move(bytes), std::move(done), std::move(options));
}

} // namespace codrive::sdo
