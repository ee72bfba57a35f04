// SPDX-License-Identifier: Apache-2.0
// The CANopen conversation decoder: one text per frame, with state across frames (SDO
// reassembly, PDO mappings learned from configuration traffic, guarding, identities).
#pragma once

#include <codrive/core/cob_id.hpp>
#include <codrive/dump/object_catalog.hpp>
#include <codrive/dump/pdo_tracker.hpp>
#include <codrive/dump/profile.hpp>
#include <codrive/dump/record.hpp>
#include <codrive/dump/sdo_tracker.hpp>
#include <codrive/dump/stats.hpp>

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::dump {

/// CANopen services, for `--only` and colours.
enum class Service : std::uint8_t { Nmt, Sync, Time, Emcy, Heartbeat, Sdo, Pdo, Lss, Other, Error };
inline constexpr std::uint32_t kAllServices = 0x3FF;
[[nodiscard]] std::string_view to_string(Service s); ///< "nmt", "sync", ..., "hb", "error"
/// Parses "nmt,emcy,sdo,pdo,sync,hb,time,lss,other,error" into a bit mask (1 << Service).
/// nullopt names the first unknown word in `bad`.
[[nodiscard]] std::optional<std::uint32_t> parse_service_list(std::string_view list,
                                                              std::string& bad);

enum class Severity : std::uint8_t { Info, Notice, Warning, Error };
[[nodiscard]] std::string_view to_string(Severity s);

/// The decode of one frame.
struct Decoded {
    Service service = Service::Other;
    NodeId node = 0;
    Severity severity = Severity::Info;
    bool timed = true; ///< the record carries a timestamp a trace can hold
    fmt::memory_buffer text;
};

/// An event not carried by the frame being decoded (an SDO request that got no answer, a step
/// back in time).
struct Note {
    std::int64_t ts_ns = 0;
    bool timed = true; ///< ts_ns is a time (a transfer of untimed frames ends without one)
    Service service = Service::Sdo;
    NodeId node = 0;
    Severity severity = Severity::Error;
    std::string event; ///< "timeout", "unfinished", "time step"
    std::string text;
};

struct DecoderOptions {
    std::int64_t sdo_timeout_ns =
        1'000'000'000; ///< an SDO request unanswered this long is reported
};

class Decoder {
public:
    explicit Decoder(DecoderOptions options = {}, Stats* stats = nullptr);

    /// Uses an EDS/DCF for a node: object names and types, default PDO parameters, identity.
    void set_description(NodeId node, std::shared_ptr<const DeviceDescription> desc);
    void set_profiles(const ProfileRegistry* registry) { registry_ = registry; }
    void set_profile(NodeId node, const IDumpProfile* profile);

    /// Decodes a frame; SDO timeouts noticed on the way are appended to `notes` (they happened
    /// before this frame).
    void decode(const TraceRecord& record, Decoded& out, std::vector<Note>& notes);
    /// Reports transfers still open at the end of the input.
    void finish(std::vector<Note>& notes);

    [[nodiscard]] const ObjectCatalog& catalog() const { return catalog_; }

private:
    struct NodeState {
        bool guard_requested = false;
        std::optional<std::uint32_t> vendor;
        std::optional<std::uint32_t> product;
        const IDumpProfile* profile = nullptr;
        bool profile_pinned = false;
    };
    /// A remote frame on a COB-ID that is never requested (NMT, SYNC, TIME, EMCY, LSS): one
    /// warning instead of decoding it as data. False for the other COB-IDs.
    bool decode_stray_remote(const CobInfo& info, Decoded& out);
    void decode_nmt(const Frame& f, Decoded& out);
    void decode_sync(const Frame& f, Decoded& out);
    void decode_time(const Frame& f, Decoded& out);
    void decode_emcy(const Frame& f, NodeId node, Decoded& out);
    void decode_error_control(const Frame& f, NodeId node, std::int64_t ts, Decoded& out);
    void decode_lss(const Frame& f, bool from_master, Decoded& out);
    void decode_sdo(const Frame& f, NodeId node, bool client, std::int64_t ts, Decoded& out);
    void learn_identity(NodeId node, std::uint8_t sub, std::uint32_t value);
    /// Finds the clock of `iface` (clock_), notices a step back in its time and moves the
    /// time-keeping state to the new time.
    void follow_time(std::string_view iface, std::int64_t ts, std::vector<Note>& notes);
    void collect_stalls(std::vector<SdoStall>& stalls, std::vector<Note>& notes,
                        std::string_view event);

    DecoderOptions options_;
    Stats* stats_;
    ObjectCatalog catalog_;
    SdoTracker sdo_;
    PdoTracker pdo_;
    const ProfileRegistry* registry_ = nullptr;
    std::array<NodeState, kMaxNodeId + 1> nodes_{};
    /// The record being decoded carries a timestamp a trace can hold (0..kMaxTraceTimeNs; a
    /// library user's record with another is decoded as untimed).
    bool timed_ = true;
    /// Each interface's time: frames of several interfaces interleave out of order (two
    /// captures of one minute concatenated, a live capture reading one socket's backlog before
    /// the next), so times are compared, and SDO transfers timed, only within one interface.
    struct InterfaceClock {
        std::string iface;
        std::int64_t latest_ns = 0;     ///< since its last step back
        std::int64_t next_check_ns = 0; ///< the next SDO timeout scan of its transfers
        std::uint32_t stretch = 0;      ///< the stretch of time it is in (see follow_time)
    };
    /// Interfaces beyond the 32nd share the last clock.
    static constexpr std::size_t kMaxClocks = 32;
    std::vector<InterfaceClock> clocks_;
    std::uint32_t stretch_ = 0; ///< the newest stretch an interface has stepped back into
    std::uint8_t clock_ = 0;    ///< the clock of the record being decoded
    std::vector<SdoStall> stalls_;
};

} // namespace codrive::dump
