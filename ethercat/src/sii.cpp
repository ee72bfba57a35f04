// SPDX-License-Identifier: Apache-2.0
// SII EEPROM parsing and building (ETG.2010 §2: header words, categories).
#include <codrive/ethercat/error.hpp>
#include <codrive/ethercat/sii.hpp>

#include <codrive/core/endian.hpp>

#include <algorithm>

namespace codrive::ethercat {
namespace {

constexpr std::size_t byte_of(std::uint16_t word) {
    return static_cast<std::size_t>(word) * 2;
}

void put_word(std::vector<std::uint8_t>& img, std::uint16_t word, std::uint16_t v) {
    if (img.size() < byte_of(word) + 2) {
        img.resize(byte_of(word) + 2, 0);
    }
    put_le<std::uint16_t>(img.data() + byte_of(word), v);
}

void put_dword(std::vector<std::uint8_t>& img, std::uint16_t word, std::uint32_t v) {
    put_word(img, word, static_cast<std::uint16_t>(v));
    put_word(img, static_cast<std::uint16_t>(word + 1), static_cast<std::uint16_t>(v >> 16));
}

void append_category(std::vector<std::uint8_t>& img, std::uint16_t type,
                     std::vector<std::uint8_t> payload) {
    if (payload.size() % 2 != 0) {
        payload.push_back(0);
    }
    const std::size_t at = img.size();
    img.resize(at + 4 + payload.size());
    put_le<std::uint16_t>(img.data() + at, type);
    put_le<std::uint16_t>(img.data() + at + 2, static_cast<std::uint16_t>(payload.size() / 2));
    std::copy(payload.begin(), payload.end(), img.begin() + static_cast<std::ptrdiff_t>(at + 4));
}

} // namespace

std::uint8_t sii_checksum(std::span<const std::uint8_t> first_14_bytes) {
    std::uint8_t crc = 0xFF;
    for (std::size_t i = 0; i < 14 && i < first_14_bytes.size(); ++i) {
        crc = static_cast<std::uint8_t>(crc ^ first_14_bytes[i]);
        for (int b = 0; b < 8; ++b) {
            crc = (crc & 0x80) != 0 ? static_cast<std::uint8_t>((crc << 1) ^ 0x07)
                                    : static_cast<std::uint8_t>(crc << 1);
        }
    }
    return crc;
}

std::optional<std::size_t> sii_categories_end(std::span<const std::uint8_t> eeprom) {
    std::size_t pos = byte_of(sii_addr::kFirstCategory);
    while (pos + 2 <= eeprom.size()) {
        const auto type = get_le<std::uint16_t>(eeprom.data() + pos);
        if (type == sii_cat::kEnd) {
            return pos + 2;
        }
        if (pos + 4 > eeprom.size()) {
            return std::nullopt;
        }
        pos += 4 + 2 * static_cast<std::size_t>(get_le<std::uint16_t>(eeprom.data() + pos + 2));
    }
    return std::nullopt;
}

Result<SiiInfo> parse_sii(std::span<const std::uint8_t> eeprom) {
    if (eeprom.size() < byte_of(sii_addr::kFirstCategory)) {
        return fail(EcatErrc::SiiError);
    }
    const auto word = [&](std::uint16_t w) {
        return get_le<std::uint16_t>(eeprom.data() + byte_of(w));
    };
    const auto dword = [&](std::uint16_t w) {
        return get_le<std::uint32_t>(eeprom.data() + byte_of(w));
    };
    SiiInfo info;
    info.checksum_ok = sii_checksum(eeprom.first(14)) == eeprom[byte_of(sii_addr::kChecksum)];
    info.alias = word(sii_addr::kConfiguredAlias);
    info.vendor_id = dword(sii_addr::kVendorId);
    info.product_code = dword(sii_addr::kProductCode);
    info.revision = dword(sii_addr::kRevision);
    info.serial = dword(sii_addr::kSerial);
    info.rx_mailbox_offset = word(sii_addr::kStdRxMailboxOffset);
    info.rx_mailbox_size = word(sii_addr::kStdRxMailboxSize);
    info.tx_mailbox_offset = word(sii_addr::kStdTxMailboxOffset);
    info.tx_mailbox_size = word(sii_addr::kStdTxMailboxSize);
    info.mailbox_protocols = word(sii_addr::kMailboxProtocol);

    std::size_t pos = byte_of(sii_addr::kFirstCategory);
    std::uint8_t name_index = 0;
    while (pos + 2 <= eeprom.size()) {
        const auto type = get_le<std::uint16_t>(eeprom.data() + pos);
        if (type == sii_cat::kEnd) {
            break;
        }
        if (pos + 4 > eeprom.size()) {
            return fail(EcatErrc::SiiError);
        }
        const std::size_t len =
            2 * static_cast<std::size_t>(get_le<std::uint16_t>(eeprom.data() + pos + 2));
        if (pos + 4 + len > eeprom.size()) {
            return fail(EcatErrc::SiiError);
        }
        const auto cat = eeprom.subspan(pos + 4, len);
        if (type == sii_cat::kStrings && !cat.empty()) {
            std::size_t p = 1;
            for (unsigned i = 0; i < cat[0]; ++i) {
                if (p >= cat.size() || p + 1 + cat[p] > cat.size()) {
                    return fail(EcatErrc::SiiError);
                }
                info.strings.emplace_back(reinterpret_cast<const char*>(cat.data() + p + 1),
                                          cat[p]);
                p += 1 + cat[p];
            }
        } else if (type == sii_cat::kGeneral && cat.size() >= 4) {
            name_index = cat[3]; // ETG.2010 Table 4: NameIdx at byte 3
        } else if (type == sii_cat::kFmmu) {
            info.fmmu_usage.assign(cat.begin(), cat.end());
        } else if (type == sii_cat::kSyncManager) {
            for (std::size_t p = 0; p + 8 <= cat.size(); p += 8) {
                SiiSyncManager sm;
                sm.start = get_le<std::uint16_t>(cat.data() + p);
                sm.length = get_le<std::uint16_t>(cat.data() + p + 2);
                sm.control = cat[p + 4];
                sm.enable = cat[p + 6];
                sm.type = static_cast<SmType>(cat[p + 7]);
                info.sync_managers.push_back(sm);
            }
        }
        pos += 4 + len;
    }
    if (name_index > 0 && name_index <= info.strings.size()) {
        info.name = info.strings[name_index - 1U];
    }
    return info;
}

std::vector<std::uint8_t> build_sii(const SiiInfo& info) {
    std::vector<std::uint8_t> img(byte_of(sii_addr::kFirstCategory), 0);
    put_word(img, 0x0000, 0x0C80); // PDI control: no PDI (simulated device), sensible default
    put_word(img, sii_addr::kConfiguredAlias, info.alias);
    img[byte_of(sii_addr::kChecksum)] = sii_checksum(std::span<const std::uint8_t>(img).first(14));
    put_dword(img, sii_addr::kVendorId, info.vendor_id);
    put_dword(img, sii_addr::kProductCode, info.product_code);
    put_dword(img, sii_addr::kRevision, info.revision);
    put_dword(img, sii_addr::kSerial, info.serial);
    put_word(img, sii_addr::kStdRxMailboxOffset, info.rx_mailbox_offset);
    put_word(img, sii_addr::kStdRxMailboxSize, info.rx_mailbox_size);
    put_word(img, sii_addr::kStdTxMailboxOffset, info.tx_mailbox_offset);
    put_word(img, sii_addr::kStdTxMailboxSize, info.tx_mailbox_size);
    put_word(img, sii_addr::kMailboxProtocol, info.mailbox_protocols);
    put_word(img, sii_addr::kSize, 0x000F); // 16 KiBit - 1 (ETG.2010: size in KiBit minus 1)
    put_word(img, sii_addr::kVersion, 1);

    std::vector<std::string> strings = info.strings;
    if (strings.empty() && !info.name.empty()) {
        strings.push_back(info.name);
    }
    std::vector<std::uint8_t> str_cat{static_cast<std::uint8_t>(strings.size())};
    for (const auto& s : strings) {
        const std::size_t n = std::min<std::size_t>(s.size(), 255);
        str_cat.push_back(static_cast<std::uint8_t>(n));
        str_cat.insert(str_cat.end(), s.begin(), s.begin() + static_cast<std::ptrdiff_t>(n));
    }
    append_category(img, sii_cat::kStrings, std::move(str_cat));

    std::vector<std::uint8_t> general(32, 0);
    general[3] = strings.empty() ? 0 : 1; // NameIdx: first string
    // CoE details (ETG.2010 Table 6): SDO (bit 0), SDO information (1), PDO assignment (2), PDO
    // configuration (3), complete access (5): what codrive's CoE slaves serve and what their ESI
    // files state (Mailbox/CoE SdoInfo, PdoAssign, PdoConfig).
    general[5] = (info.mailbox_protocols & mbx_proto::kCoe) != 0 ? 0x2F : 0;
    general[6] = (info.mailbox_protocols & mbx_proto::kFoe) != 0 ? 0x01 : 0; // FoE details
    // Physical ports, 4 bits each (ETG.2010 Table 6: 1 = MII): ports 0 and 1, as the ESC's port
    // descriptor 0x0007 and the ESI's Physics="YY" say.
    general[16] = 0x11;
    append_category(img, sii_cat::kGeneral, std::move(general));

    if (!info.fmmu_usage.empty()) {
        append_category(img, sii_cat::kFmmu, info.fmmu_usage);
    }
    std::vector<std::uint8_t> sms;
    for (const auto& sm : info.sync_managers) {
        std::uint8_t b[8]{};
        put_le<std::uint16_t>(b, sm.start);
        put_le<std::uint16_t>(b + 2, sm.length);
        b[4] = sm.control;
        b[6] = sm.enable;
        b[7] = static_cast<std::uint8_t>(sm.type);
        sms.insert(sms.end(), b, b + 8);
    }
    if (!sms.empty()) {
        append_category(img, sii_cat::kSyncManager, std::move(sms));
    }
    img.push_back(0xFF);
    img.push_back(0xFF);
    return img;
}

} // namespace codrive::ethercat
