// SPDX-License-Identifier: Apache-2.0
// EMCY consumer (CiA 301 §7.2.7): decoding, per-node history and active-error state.
#pragma once

#include <codrive/core/frame.hpp>
#include <codrive/core/time.hpp>
#include <codrive/emcy/history.hpp>
#include <codrive/emcy/message.hpp>
#include <codrive/emcy/text_provider.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace codrive::emcy {

struct EmcyEvent {
    EmcyMessage message;
    TimePoint time{};
    /// Code 0000h: the node reports that it has no active error any more.
    bool reset = false;
    std::string text; ///< describe() with the node's text provider
};

/// Active-error state of one node: codes reported since the last 0000h.
struct ActiveErrors {
    static constexpr std::size_t kMaxCodes = 8;
    std::array<std::uint16_t, kMaxCodes> codes{}; ///< distinct codes, oldest first
    std::size_t count = 0;                        ///< how many of `codes` are valid
    std::uint8_t error_register = 0;              ///< from the last EMCY
    [[nodiscard]] bool any() const { return count != 0; }
    [[nodiscard]] bool contains(std::uint16_t code) const;
};

/// Listens to EMCY of every node on the predefined COB-IDs 081h..0FFh.
class EmcyConsumer {
public:
    using Handler = std::function<void(const EmcyEvent&)>;

    void set_handler(Handler handler) { handler_ = std::move(handler); }
    /// Vendor text for every node without its own provider (nullptr removes).
    void set_text_provider(std::shared_ptr<const IEmcyTextProvider> provider);
    /// Vendor text for one node (a drive profile). Ignored for invalid node ids.
    void set_text_provider(NodeId node, std::shared_ptr<const IEmcyTextProvider> provider);

    /// Handles EMCY frames; malformed ones are counted. Returns true if it was an EMCY.
    bool on_frame(const Frame& frame, TimePoint now);

    [[nodiscard]] const EmcyHistory& history(NodeId node) const;
    [[nodiscard]] const ActiveErrors& active(NodeId node) const;
    /// Forgets a node's history and active errors (e.g. after its reset).
    void clear(NodeId node);
    /// The sentence for a message with the node's provider.
    [[nodiscard]] std::string describe(const EmcyMessage& m) const;

    [[nodiscard]] std::uint64_t received() const { return received_; }
    [[nodiscard]] std::uint64_t malformed() const { return malformed_; }
    [[nodiscard]] std::uint64_t short_frames() const { return short_frames_; }

private:
    [[nodiscard]] const IEmcyTextProvider* provider(NodeId node) const;

    std::array<EmcyHistory, kMaxNodeId + 1> history_{};
    std::array<ActiveErrors, kMaxNodeId + 1> active_{};
    std::array<std::shared_ptr<const IEmcyTextProvider>, kMaxNodeId + 1> providers_{};
    std::shared_ptr<const IEmcyTextProvider> default_provider_;
    Handler handler_;
    std::uint64_t received_ = 0;
    std::uint64_t malformed_ = 0;
    std::uint64_t short_frames_ = 0;
};

} // namespace codrive::emcy
