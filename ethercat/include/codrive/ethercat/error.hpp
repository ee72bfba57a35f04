// SPDX-License-Identifier: Apache-2.0
// Errors of the EtherCAT master (ETG.1000): lost frames, working counters, ESM, SII, mailbox.
#pragma once

#include <system_error>

namespace codrive::ethercat {

/// EtherCAT master errors. SDO aborts received over CoE are reported with the shared
/// codrive::SdoAbort codes instead (codrive/core/sdo_abort.hpp).
enum class EcatErrc {
    NoResponse = 1,      ///< no frame came back before the timeout (after retries)
    WorkingCounter,      ///< a datagram's working counter was not the expected one
    NoSlaves,            ///< the segment has no slave
    NoSuchSlave,         ///< slave position out of range
    StateChangeRefused,  ///< the slave set the AL error flag (AL status code tells why)
    StateChangeTimeout,  ///< the slave did not reach the requested state in time
    SiiTimeout,          ///< the SII EEPROM interface stayed busy
    SiiError,            ///< the SII EEPROM interface reported an error or bad content
    MailboxNotSupported, ///< the slave has no mailbox or no CoE
    MailboxTimeout,      ///< no mailbox answer in time
    MailboxError,        ///< mailbox error reply or malformed mailbox data
    ProtocolError,       ///< a CoE reply did not match the request
    NotConfigured,       ///< process data not mapped yet
    FrameTooLarge,       ///< datagrams do not fit one Ethernet frame
    InvalidFrame,        ///< a received frame is not a well-formed EtherCAT frame
    PermissionDenied,    ///< raw sockets need CAP_NET_RAW
    Cancelled,           ///< the master ended a mailbox transfer before the slave answered
};

const std::error_category& ecat_category();
std::error_code make_error_code(EcatErrc e);

} // namespace codrive::ethercat

template <>
struct std::is_error_code_enum<codrive::ethercat::EcatErrc> : std::true_type {};
