// SPDX-License-Identifier: Apache-2.0
// SDO server serving an ObjectDictionary (CiA 301 §7.2.4): expedited, segmented and block
// transfers, domain streaming hooks and access hooks.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/cob_id.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/sdo/error.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <tl/expected.hpp>

namespace codrive::sdo {

namespace detail {
struct ServerSession;
}

struct ServerConfig {
    NodeId node = 1;
    /// COB-IDs; 0 = default channel: requests on 600h+node, responses on 580h+node.
    std::uint32_t request_id = 0;
    std::uint32_t response_id = 0;
    /// Abort with 0x05040000 when the client goes silent this long mid-transfer.
    Duration timeout = std::chrono::milliseconds(1000);
    /// Block download: sub-block size we ask for (1..127).
    std::uint8_t block_size = 127;
    bool crc = true;
    /// Answer uploads of 1..4 bytes expedited (some devices always segment; tests use that).
    bool expedited_upload = true;
    /// Block download: acknowledge early when a sub-block stalls (its last segment was lost).
    Duration block_gap_timeout = std::chrono::milliseconds(100);
    /// Block download: send the initiate or sub-block response again when nothing of the
    /// sub-block it asks for arrives within `block_gap_timeout`. Off by default: CiA 301
    /// §7.2.4.3.9-10 has one response per step, and a CAN frame reaches every node or none, so
    /// the copy reaches a client that already has the original. python-canopen, slower than
    /// 100 ms to send its first segment, took the copy for its next answer and aborted with
    /// 05040001h. Only for lossy links where the response itself may vanish (fault injection).
    bool repeat_block_responses = false;
};

/// Streams a large DOMAIN upload without the data sitting in the dictionary.
struct DomainReader {
    std::size_t size = 0;
    /// Fills `out` completely with the next bytes, or returns the abort code to send.
    std::function<tl::expected<void, SdoAbort>(std::span<std::uint8_t> out)> read;
};
/// Receives a DOMAIN download piece by piece.
struct DomainWriter {
    std::function<tl::expected<void, SdoAbort>(std::span<const std::uint8_t> data)> write;
    /// All data arrived (the size checks passed); an abort code refuses the whole download.
    std::function<tl::expected<void, SdoAbort>()> finish;
    /// The transfer was aborted or timed out (optional).
    std::function<void()> cancel;
};
using DomainUploadHandler =
    std::function<tl::expected<DomainReader, SdoAbort>(std::uint16_t index, std::uint8_t sub)>;
using DomainDownloadHandler = std::function<tl::expected<DomainWriter, SdoAbort>(
    std::uint16_t index, std::uint8_t sub, std::optional<std::size_t> size)>;
/// Checked before every transfer: return an abort code to refuse it (e.g. 0x08000022 in the
/// present device state, or PDO mapping changes while the PDO is valid).
using AccessHook = std::function<std::optional<SdoAbort>(std::uint16_t index, std::uint8_t sub,
                                                         Direction direction)>;

struct ServerStats {
    std::uint64_t requests = 0;
    std::uint64_t completed = 0;
    std::uint64_t aborts_sent = 0;
    std::uint64_t aborts_received = 0;
    std::uint64_t timeouts = 0;
    std::uint64_t frames_ignored = 0;
    std::uint64_t early_acks = 0; ///< sub-blocks acknowledged by the gap timer
    /// Requests ignored as byte-identical repeats or late sub-block responses (docs/sdo.md).
    std::uint64_t repeats_ignored = 0;
    /// Block download initiate / sub-block responses sent again because no segment followed.
    std::uint64_t acks_repeated = 0;
};

/// The SDO server of one node. Reads and writes go through the ObjectDictionary, whose access,
/// length and range checks give the abort codes; write hooks there run on completed downloads.
class SdoServer final : public ITimed {
public:
    SdoServer(ObjectDictionary& od, ICanBus& bus, ServerConfig config);
    ~SdoServer() override;
    SdoServer(const SdoServer&) = delete;
    SdoServer& operator=(const SdoServer&) = delete;

    /// Serves uploads of index:sub from `handler` instead of the dictionary.
    void set_domain_upload(std::uint16_t index, std::uint8_t sub, DomainUploadHandler handler);
    /// Sends downloads to index:sub to `handler` instead of the dictionary.
    void set_domain_download(std::uint16_t index, std::uint8_t sub, DomainDownloadHandler handler);
    void set_access_hook(AccessHook hook) { access_hook_ = std::move(hook); }

    /// Feeds a received frame; true if it was a request on this server's channel.
    bool on_frame(const Frame& frame, TimePoint now);
    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

    [[nodiscard]] bool busy() const;
    [[nodiscard]] const ServerStats& stats() const { return stats_; }
    [[nodiscard]] const ServerConfig& config() const { return config_; }
    [[nodiscard]] std::uint32_t request_id() const { return request_id_; }

private:
    ObjectDictionary& od_;
    ICanBus& bus_;
    ServerConfig config_;
    std::uint32_t request_id_;
    std::uint32_t response_id_;
    std::map<std::uint32_t, DomainUploadHandler> upload_handlers_;
    std::map<std::uint32_t, DomainDownloadHandler> download_handlers_;
    AccessHook access_hook_;
    std::unique_ptr<detail::ServerSession> session_;
    ServerStats stats_;
};

} // namespace codrive::sdo
