// SPDX-License-Identifier: Apache-2.0
// EMCY consumer: history and active errors per node (CiA 301 §7.2.7).
#include <codrive/emcy/consumer.hpp>

#include <algorithm>

namespace codrive::emcy {

namespace {
const EmcyHistory kNoHistory{};
const ActiveErrors kNoActive{};
} // namespace

bool ActiveErrors::contains(std::uint16_t code) const {
    return std::find(codes.begin(), codes.begin() + static_cast<std::ptrdiff_t>(count), code) !=
           codes.begin() + static_cast<std::ptrdiff_t>(count);
}

void EmcyConsumer::set_text_provider(std::shared_ptr<const IEmcyTextProvider> provider) {
    default_provider_ = std::move(provider);
}

void EmcyConsumer::set_text_provider(NodeId node,
                                     std::shared_ptr<const IEmcyTextProvider> provider) {
    if (valid_node_id(node)) {
        providers_[node] = std::move(provider);
    }
}

const IEmcyTextProvider* EmcyConsumer::provider(NodeId node) const {
    if (valid_node_id(node) && providers_[node]) {
        return providers_[node].get();
    }
    return default_provider_.get();
}

std::string EmcyConsumer::describe(const EmcyMessage& m) const {
    return emcy::describe(m, provider(m.node));
}

bool EmcyConsumer::on_frame(const Frame& frame, TimePoint now) {
    if (frame.extended() || frame.id <= cob::kEmcy || frame.id > cob::kEmcy + kMaxNodeId) {
        return false;
    }
    auto m = parse_emcy(frame);
    if (!m) {
        ++malformed_;
        return false;
    }
    ++received_;
    if (m->length < 8) {
        ++short_frames_; // CiA 301 requires 8 bytes; decoded anyway for diagnosis
    }
    const NodeId node = m->node;
    history_[node].push(EmcyRecord{*m, now});
    auto& act = active_[node];
    act.error_register = m->error_register;
    if (m->is_reset()) {
        // 0000h "error reset or no error": every error of the node has gone (CiA 301 §7.2.7.1).
        act.count = 0;
    } else if (!act.contains(m->error_code)) {
        if (act.count == ActiveErrors::kMaxCodes) {
            std::rotate(act.codes.begin(), act.codes.begin() + 1, act.codes.end());
            --act.count;
        }
        act.codes[act.count++] = m->error_code;
    }
    if (handler_) {
        handler_(EmcyEvent{*m, now, m->is_reset(), describe(*m)});
    }
    return true;
}

const EmcyHistory& EmcyConsumer::history(NodeId node) const {
    return valid_node_id(node) ? history_[node] : kNoHistory;
}

const ActiveErrors& EmcyConsumer::active(NodeId node) const {
    return valid_node_id(node) ? active_[node] : kNoActive;
}

void EmcyConsumer::clear(NodeId node) {
    if (valid_node_id(node)) {
        history_[node].clear();
        active_[node] = ActiveErrors{};
    }
}

} // namespace codrive::emcy
