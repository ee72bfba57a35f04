// SPDX-License-Identifier: Apache-2.0
// Transport-neutral SDO client transfer (expedited and segmented, CiA 301 §7.2.4.3): one reply
// in, the next request out. Used by the CAN client (sdo::SdoClient) and by CoE (ethercat/).
#pragma once

#include <codrive/sdo/error.hpp>
#include <codrive/sdo/protocol.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace codrive::sdo {

/// How a transport carries SDO data beyond CiA 301's 8 bytes. The defaults are CAN's.
struct SdoFraming {
    /// Most data bytes one download segment request carries (CAN: 7; CoE: what the slave's
    /// receive mailbox holds after the segment's command byte, ETG.1000.6 §5.6.2.3).
    std::size_t segment_room = kSegmentData;
    /// Data bytes a non-expedited initiate download request carries after its size (CAN: 0;
    /// CoE "normal transfer": the mailbox room after the 8 bytes, ETG.1000.6 §5.6.2.2).
    std::size_t initiate_room = 0;
    /// CoE complete access (ETG.1000.6 §5.6.2.1.1): the request sets kCompleteAccessBit and the
    /// answer may name the sub-index the access starts from.
    bool complete_access = false;
};

/// The detail sentence when a download of `size` bytes cannot be announced (the CiA 301 size
/// field is 32 bits), nullopt when it can.
[[nodiscard]] std::optional<std::string> download_too_large(std::size_t size);

/// The most an upload's own buffer reserves before its data arrives (CAN and CoE alike). The size
/// a server indicates — a garbage or hostile 4 GiB included — pre-sizes the buffer up to this;
/// beyond it the memory follows the bytes that actually arrive. (A 16 MiB cap cost the fuzzer 70 %
/// of its time touching pages no data ever filled.)
inline constexpr std::size_t kMaxUploadReserve = 64U * 1024U;

/// The protocol a server response belongs to: 1 expedited/segmented upload, 2 download, 3 block
/// download, 4 block upload, 0 none of the client's (aborts and client frames).
[[nodiscard]] int response_family(FrameKind kind);

/// Whether a server response that is not an abort answers another transfer than the one
/// expecting `want` (a late answer to a request that timed out, or a repeat). In the initiate
/// phase only the expected response naming the transfer's object (`ours`) is an answer: the
/// server's first answer to an initiate request names the object (CiA 301 §7.2.4.3). Later an
/// initiate response (it only ever answers an initiate request) or a response of another
/// protocol belongs to an earlier transfer; a frame with a reserved command specifier does not,
/// the transfer rejects it. One rule for CAN, where answers cross on the bus, and CoE, where a
/// late answer waits in the slave's mailbox ahead of the next transfer's (ETG.1000.6 §5.6.2).
[[nodiscard]] bool answers_another_transfer(FrameKind got, FrameKind want, bool initiate_phase,
                                            bool ours);

/// The caller's side of the data: an upload writes into it, a download reads from it.
class ISdoData {
public:
    virtual ~ISdoData() = default;
    /// Upload: called once before data with the size the server indicated; false refuses it.
    virtual bool begin(std::optional<std::size_t> size) = 0;
    /// Upload: the next piece of data, in order; false refuses it.
    virtual bool write(std::span<const std::uint8_t> data) = 0;
    /// Download: fills `out` completely with the next bytes; false when the data cannot be read.
    virtual bool read(std::span<std::uint8_t> out) = 0;
};

/// One expedited or segmented SDO transfer seen from the client. Sans-I/O: begin_*() and
/// on_reply() fill request() (the 8-byte CiA 301 frame plus, on CoE, the data past it) and
/// return what to do; the transport sends, times out, retries and drops back-to-back repeats.
/// Every check the client makes on a reply lives here: the answer names the object, it is not
/// the late answer of another transfer, it is the response the phase expects, segment toggles
/// alternate, segments add up to the
/// indicated size, and a zero-length segment that is not the last ends the transfer (it would
/// otherwise loop forever).
class SdoClientMachine {
public:
    enum class Step : std::uint8_t {
        Send,   ///< send request() and wait for the reply
        Done,   ///< the transfer succeeded
        Failed, ///< failure() says why; send request() first when failure().abort is set
        Ignore, ///< the reply answers no step of this transfer (answers_another_transfer(), or
                ///< an abort naming another object): dropped, the transport's timeout runs on
    };
    enum class Phase : std::uint8_t {
        Idle,
        InitiateUpload,
        UploadSegment,
        InitiateDownload,
        DownloadSegment,
        Finished,
    };
    /// Why the transfer failed, as SdoError tells it.
    struct Failure {
        std::error_code cause; ///< SdoErrc, or the abort code (sdo_abort_category)
        AbortOrigin origin = AbortOrigin::None;
        std::string detail;
        /// The abort code request() carries to the server, if the client aborts.
        std::optional<std::uint32_t> abort;
    };

    SdoClientMachine() = default;
    /// A transfer of index:subindex; `data` must outlive the machine.
    SdoClientMachine(ISdoData& data, SdoFraming framing, std::uint16_t index, std::uint8_t subindex)
        : data_(&data), framing_(framing), index_(index), subindex_(subindex) {}

    /// Initiate upload request into request(). Always Send.
    Step begin_upload();
    /// Initiate download of `size` bytes: expedited when `expedited` allows and 1..4 bytes,
    /// otherwise segmented (CoE: with up to initiate_room bytes in the initiate request). Failed
    /// (no abort: nothing was sent) when the size does not fit 32 bits or the data cannot be read.
    Step begin_download(std::size_t size, bool expedited);
    /// A reply: the parsed 8-byte frame and, on CoE, the bytes after it in the same message.
    /// An answer of another transfer (noted for unanswered()), and an abort naming another
    /// object, is Ignore; an abort naming this object ends the transfer.
    Step on_reply(const FrameInfo& reply, std::span<const std::uint8_t> extra = {});
    /// Remembers a dropped answer of another transfer for unanswered(): the first object an
    /// initiate response named that is not this transfer's (with complete access, another
    /// index), and frames with a reserved command specifier. (CAN's client calls it for the block
    /// transfers it runs itself.)
    void note_stray(const FrameInfo& reply);
    /// The transport's timeout expired with the initiate request unanswered: Failed when the
    /// dropped answers explain it (one named another object: wrong_object(); frames with a
    /// reserved command specifier: abort 0x05040001), Ignore when nothing came (the transport
    /// reports its own timeout).
    Step unanswered();
    /// The server's abort frame `reply` ends the transfer (in any phase, block transfers too).
    Step server_abort(const FrameInfo& reply);
    /// The server's answers named another object in the initiate phase and none named ours: the
    /// failure CAN's client reports when its timeout expires (abort 0x08000000 into request()).
    Step wrong_object(std::uint16_t index, std::uint8_t subindex);
    /// An abort request into request() and Failed, for a failure the transport detected.
    Step abort(std::uint32_t code, std::error_code cause, std::string detail,
               AbortOrigin origin = AbortOrigin::Client);

    [[nodiscard]] const Payload& request() const { return request_; }
    /// CoE only: data bytes sent after the 8 bytes of request() (empty on CAN).
    [[nodiscard]] std::span<const std::uint8_t> request_extra() const { return extra_; }
    [[nodiscard]] const Failure& failure() const { return failure_; }
    [[nodiscard]] Phase phase() const { return phase_; }
    [[nodiscard]] Protocol protocol() const { return protocol_; }
    [[nodiscard]] Direction direction() const { return direction_; }
    [[nodiscard]] std::uint16_t index() const { return index_; }
    [[nodiscard]] std::uint8_t subindex() const { return subindex_; }
    /// Bytes transferred so far, and the total when known.
    [[nodiscard]] std::size_t done() const { return done_; }
    [[nodiscard]] std::optional<std::size_t> total() const { return total_; }
    /// The last reply moved a segment (the moment to report progress).
    [[nodiscard]] bool progressed() const { return progressed_; }
    /// "7 of 30 bytes" / "7 bytes": how far the transfer came, for sentences.
    [[nodiscard]] std::string position() const;

private:
    Step on_initiate_upload(const FrameInfo& reply, std::span<const std::uint8_t> extra);
    Step on_upload_segment(const FrameInfo& reply, std::span<const std::uint8_t> extra);
    Step on_download_response(const FrameInfo& reply);
    Step client_abort(SdoAbort code, std::string detail);
    Step next_download_segment();
    Step source_failed();
    [[nodiscard]] bool names_our_object(const FrameInfo& reply) const;
    void set_request(const Payload& p);
    Step fail(std::error_code cause, std::string detail, AbortOrigin origin,
              std::optional<std::uint32_t> abort);

    ISdoData* data_ = nullptr;
    SdoFraming framing_;
    std::uint16_t index_ = 0;
    std::uint8_t subindex_ = 0;
    Phase phase_ = Phase::Idle;
    Direction direction_ = Direction::Upload;
    Protocol protocol_ = Protocol::Unknown;
    bool toggle_ = false;
    bool last_sent_ = false;
    bool progressed_ = false;
    std::size_t done_ = 0;
    std::optional<std::size_t> total_;
    Payload request_{};
    std::vector<std::uint8_t> extra_;
    Failure failure_;
    std::optional<std::pair<std::uint16_t, std::uint8_t>> stray_object_; ///< see note_stray()
    bool stray_invalid_ = false;
};

} // namespace codrive::sdo
