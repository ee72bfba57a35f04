// SPDX-License-Identifier: Apache-2.0
// NMT master: command transmission and state bookkeeping.
#include <codrive/nmt/master.hpp>

namespace codrive::nmt {

VoidResult NmtMaster::send(NmtCommand command, NodeId node) {
    auto frame = make_command_frame(command, node);
    if (!frame) {
        return fail(frame.error());
    }
    if (auto r = bus_.send(*frame); !r) {
        return r;
    }
    ++sent_;
    // CiA 301 has no acknowledgement for NMT commands. After a reset the old state is stale
    // until the boot-up arrives, so forget it; other commands are confirmed by the next
    // heartbeat or guarding reply.
    if (command == NmtCommand::ResetNode || command == NmtCommand::ResetCommunication) {
        if (node == kAllNodes) {
            for (unsigned n = 1; n <= kMaxNodeId; ++n) {
                table_.set_state(static_cast<NodeId>(n), NmtState::Unknown);
            }
        } else {
            table_.set_state(node, NmtState::Unknown);
        }
    }
    return {};
}

} // namespace codrive::nmt
