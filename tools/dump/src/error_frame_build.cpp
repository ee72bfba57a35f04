// SPDX-License-Identifier: Apache-2.0
// SocketCAN error frames built from trace lines.
#include <codrive/dump/error_frame_build.hpp>

#include <linux/can/error.h>

namespace codrive::dump {
namespace {
void add_counters(Frame& f, int tec, int rec) {
    if (tec >= 0 || rec >= 0) {
        f.id |= CAN_ERR_CNT;
        f.data[6] = static_cast<std::uint8_t>(tec < 0 ? 0 : (tec > 255 ? 255 : tec));
        f.data[7] = static_cast<std::uint8_t>(rec < 0 ? 0 : (rec > 255 ? 255 : rec));
    }
}
Frame blank() {
    Frame f;
    f.flags = Frame::kError;
    f.len = CAN_ERR_DLC;
    return f;
}
} // namespace

Frame protocol_error_frame(std::uint8_t prot, bool on_tx, std::uint8_t location, int tec, int rec) {
    Frame f = blank();
    // Both class bits, as Linux CAN drivers (sja1000, flexcan, m_can) report a bus error with its
    // details; can-utils' asc2log and python-can write a bare Vector ErrorFrame as
    // CAN_ERR_BUSERROR alone, so either way the class says "bus error".
    f.id = CAN_ERR_PROT | CAN_ERR_BUSERROR;
    f.data[2] = static_cast<std::uint8_t>(prot | (on_tx ? CAN_ERR_PROT_TX : 0));
    f.data[3] = location;
    add_counters(f, tec, rec);
    return f;
}

Frame sja1000_ecc_error_frame(std::uint8_t ecc) {
    static constexpr std::uint8_t kType[] = {CAN_ERR_PROT_BIT, CAN_ERR_PROT_FORM,
                                             CAN_ERR_PROT_STUFF, CAN_ERR_PROT_UNSPEC};
    return protocol_error_frame(kType[ecc >> 6], (ecc & 0x20U) == 0,
                                static_cast<std::uint8_t>(ecc & 0x1FU));
}

Frame can_core_error_frame(std::uint8_t code) {
    const unsigned error = code & 0x3FU;
    const unsigned direction = code >> 6;
    std::uint8_t prot = CAN_ERR_PROT_UNSPEC;
    std::uint8_t location = CAN_ERR_PROT_LOC_UNSPEC;
    switch (error) {
    case 0:
        prot = CAN_ERR_PROT_BIT;
        break;
    case 1:
        prot = CAN_ERR_PROT_FORM;
        break;
    case 2:
        prot = CAN_ERR_PROT_STUFF;
        break;
    case 4:
        location = CAN_ERR_PROT_LOC_CRC_SEQ;
        break;
    case 5:
        prot = CAN_ERR_PROT_FORM;
        location = CAN_ERR_PROT_LOC_ACK_DEL;
        break;
    default: // 3 "other" and codes the register does not define
        break;
    }
    if (direction == 1) { // a transmitter that saw no acknowledge
        return no_ack_error_frame(prot, true, location);
    }
    return protocol_error_frame(prot, direction == 3, location);
}

Frame no_ack_error_frame(std::uint8_t prot, bool on_tx, std::uint8_t location) {
    Frame f = protocol_error_frame(
        prot, on_tx, location == CAN_ERR_PROT_LOC_UNSPEC ? CAN_ERR_PROT_LOC_ACK : location);
    f.id |= CAN_ERR_ACK;
    return f;
}

Frame state_error_frame(TraceBusState state, int tec, int rec) {
    Frame f = blank();
    switch (state) {
    case TraceBusState::BusOff:
        f.id = CAN_ERR_BUSOFF;
        break;
    case TraceBusState::Passive:
        f.id = CAN_ERR_CRTL;
        f.data[1] = CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE;
        break;
    case TraceBusState::Warning:
        f.id = CAN_ERR_CRTL;
        f.data[1] = CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING;
        break;
    case TraceBusState::Active:
        f.id = CAN_ERR_CRTL;
        f.data[1] = CAN_ERR_CRTL_ACTIVE;
        break;
    case TraceBusState::RxOverflow:
        f.id = CAN_ERR_CRTL;
        f.data[1] = CAN_ERR_CRTL_RX_OVERFLOW;
        break;
    case TraceBusState::Unknown:
        f.id = CAN_ERR_CRTL;
        f.data[1] = CAN_ERR_CRTL_UNSPEC;
        break;
    }
    add_counters(f, tec, rec);
    return f;
}

TraceBusState state_from_counters(int tec, int rec) {
    const int worst = tec > rec ? tec : rec;
    if (worst >= 128) {
        return TraceBusState::Passive;
    }
    return worst >= 96 ? TraceBusState::Warning : TraceBusState::Active;
}

} // namespace codrive::dump
