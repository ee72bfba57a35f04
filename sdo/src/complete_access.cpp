// SPDX-License-Identifier: Apache-2.0
// CoE SDO complete access over an ObjectDictionary (ETG.1000.6 §5.6.2.1.1, ETG.1020 §12.2).
#include <codrive/sdo/complete_access.hpp>

namespace codrive::sdo {

tl::expected<void, SdoAbort> check_complete(const ObjectDictionary& od, std::uint16_t index,
                                            std::uint8_t sub) {
    const Object* obj = od.find(index);
    if (obj == nullptr) {
        return tl::unexpected(SdoAbort::NoObject);
    }
    // Complete access names an ARRAY or RECORD from sub-index 0 or 1 (ETG.1000.6 §5.6.2.1.1);
    // a VAR has no entries to pack, and any other start is not a complete access.
    if (obj->code == ObjectCode::Var || sub > 1) {
        return tl::unexpected(SdoAbort::UnsupportedAccess);
    }
    return {};
}

tl::expected<std::vector<std::uint8_t>, SdoAbort>
read_complete(ObjectDictionary& od, std::uint16_t index, std::uint8_t sub) {
    if (auto ok = check_complete(od, index, sub); !ok) {
        return tl::unexpected(ok.error());
    }
    auto count = od.read(index, 0);
    if (!count) {
        return tl::unexpected(count.error());
    }
    const std::uint8_t n = count->empty() ? 0 : (*count)[0];
    std::vector<std::uint8_t> out;
    if (sub == 0) {
        out.push_back(n);
        out.push_back(0); // padding to 16 bits
    }
    for (unsigned s = 1; s <= n; ++s) {
        auto v = od.read(index, static_cast<std::uint8_t>(s));
        if (!v) {
            return tl::unexpected(v.error());
        }
        out.insert(out.end(), v->begin(), v->end());
    }
    return out;
}

tl::expected<void, SdoAbort> write_complete(ObjectDictionary& od, std::uint16_t index,
                                            std::uint8_t sub, std::span<const std::uint8_t> data) {
    if (auto ok = check_complete(od, index, sub); !ok) {
        return ok;
    }
    std::size_t pos = 0;
    std::uint8_t count = od.get<std::uint8_t>(index, 0).value_or(0);
    if (sub == 0) {
        if (data.size() < 2) {
            return tl::unexpected(SdoAbort::LengthTooLow);
        }
        count = data[0];
        pos = 2;
        const std::uint8_t zero = 0;
        if (auto r = od.write(index, 0, std::span<const std::uint8_t>(&zero, 1)); !r) {
            return r;
        }
    }
    for (unsigned s = 1; s <= count; ++s) {
        const SubObject* so = od.find(index, static_cast<std::uint8_t>(s));
        if (so == nullptr) {
            return tl::unexpected(SdoAbort::NoSubindex);
        }
        const std::size_t n = data_type_size(so->type);
        if (n == 0 || pos + n > data.size()) {
            return tl::unexpected(SdoAbort::LengthMismatch);
        }
        if (auto r = od.write(index, static_cast<std::uint8_t>(s), data.subspan(pos, n)); !r) {
            return r;
        }
        pos += n;
    }
    if (sub == 0) {
        return od.write(index, 0, std::span<const std::uint8_t>(&count, 1));
    }
    return {};
}

} // namespace codrive::sdo
