// SPDX-License-Identifier: Apache-2.0
// The EtherCAT error category.
#include <codrive/ethercat/error.hpp>

#include <string>

namespace codrive::ethercat {
namespace {

class EcatCategory final : public std::error_category {
public:
    const char* name() const noexcept override { return "codrive-ethercat"; }
    std::string message(int ev) const override {
        switch (static_cast<EcatErrc>(ev)) {
        case EcatErrc::NoResponse:
            return "no EtherCAT frame came back";
        case EcatErrc::WorkingCounter:
            return "unexpected working counter";
        case EcatErrc::NoSlaves:
            return "no EtherCAT slave answered";
        case EcatErrc::NoSuchSlave:
            return "no such slave position";
        case EcatErrc::StateChangeRefused:
            return "the slave refused the state change";
        case EcatErrc::StateChangeTimeout:
            return "the slave did not reach the requested state in time";
        case EcatErrc::SiiTimeout:
            return "the SII EEPROM stayed busy";
        case EcatErrc::SiiError:
            return "SII EEPROM error";
        case EcatErrc::MailboxNotSupported:
            return "the slave has no CoE mailbox";
        case EcatErrc::MailboxTimeout:
            return "no mailbox answer in time";
        case EcatErrc::MailboxError:
            return "mailbox error";
        case EcatErrc::ProtocolError:
            return "CoE protocol error";
        case EcatErrc::NotConfigured:
            return "process data is not configured";
        case EcatErrc::FrameTooLarge:
            return "datagrams do not fit one Ethernet frame";
        case EcatErrc::InvalidFrame:
            return "malformed EtherCAT frame";
        case EcatErrc::PermissionDenied:
            return "raw EtherCAT sockets need CAP_NET_RAW (run as root or grant cap_net_raw)";
        case EcatErrc::Cancelled:
            return "mailbox transfer cancelled before the slave answered";
        }
        return "unknown EtherCAT error";
    }
};

} // namespace

const std::error_category& ecat_category() {
    static const EcatCategory category;
    return category;
}

std::error_code make_error_code(EcatErrc e) {
    return {static_cast<int>(e), ecat_category()};
}

} // namespace codrive::ethercat
