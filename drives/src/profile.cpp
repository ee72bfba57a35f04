// SPDX-License-Identifier: Apache-2.0
// Profile look-up, identity matching, the EMCY text hook and the device object builder.
#include <codrive/drives/profile.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <fmt/format.h>

namespace codrive::drives {

std::uint16_t Profile::axis_index(std::uint16_t index, unsigned axis) const {
    if (axis <= 1) {
        return index;
    }
    const auto steps = static_cast<unsigned>(axis - 1);
    // CiA 402 §6.x: profile objects of axis n live at 6000h + (n-1) * 800h. Manufacturer
    // per-axis objects use the profile's own stride (AKD2G 50xxh → 51xxh).
    if (index >= 0x6000 && index < 0x6800) {
        return static_cast<std::uint16_t>(index + axis_offset * steps);
    }
    if (manufacturer_axis_offset != 0 && index >= 0x5000 && index < 0x5100) {
        return static_cast<std::uint16_t>(index + manufacturer_axis_offset * steps);
    }
    return index;
}

bool Profile::supports_mode(std::int8_t mode) const {
    if (mode == 0) {
        return true;
    }
    if (std::find(rejected_modes.begin(), rejected_modes.end(), mode) != rejected_modes.end()) {
        return false;
    }
    if (std::find(extra_modes.begin(), extra_modes.end(), mode) != extra_modes.end()) {
        return true;
    }
    if (mode < 0) {
        return std::any_of(manufacturer_modes.begin(), manufacturer_modes.end(),
                           [mode](const ManufacturerMode& m) { return m.value == mode; });
    }
    const std::uint32_t bit = cia402::supported_mode_bit(static_cast<cia402::Mode>(mode));
    return bit != 0 && (supported_modes & bit) != 0;
}

const ModeLayout* Profile::layout(cia402::Mode mode) const {
    for (const ModeLayout& l : layouts) {
        if (l.mode == mode) {
            return &l;
        }
    }
    return nullptr;
}

const FaultRow* Profile::fault(std::uint16_t code) const {
    for (const FaultRow& r : faults) {
        if (r.code == code) {
            return &r;
        }
    }
    return nullptr;
}

const ErrorNumberRow* Profile::error_number(std::uint8_t number) const {
    for (const ErrorNumberRow& r : error_numbers) {
        if (r.number == number) {
            return &r;
        }
    }
    return nullptr;
}

const FaultRow* Profile::axis_list_fault(std::uint16_t entry) const {
    if (const FaultRow* r = fault(entry)) {
        return r;
    }
    const std::string number = fmt::format("{}", entry);
    const FaultRow* warning = nullptr;
    for (const FaultRow& r : faults) {
        if (r.number.size() == number.size() + 1 && r.number.substr(1) == number) {
            if (!r.is_warning()) {
                return &r; // a fault list names faults first
            }
            warning = warning != nullptr ? warning : &r;
        }
    }
    return warning;
}

std::string Profile::fault_text(std::uint16_t code) const {
    const FaultRow* r = fault(code);
    if (r == nullptr) {
        return {};
    }
    if (r->number.empty()) {
        return std::string(r->text);
    }
    return fmt::format("{} {}", r->number, r->text);
}

bool Profile::has_object(std::uint16_t index) const {
    const auto& absent = absent_objects;
    if (std::find(absent.begin(), absent.end(), index) != absent.end()) {
        return false;
    }
    const auto has = [index](const ObjectSpec& s) { return s.index == index; };
    return std::any_of(object_overrides.begin(), object_overrides.end(), has) ||
           std::any_of(generic_objects().begin(), generic_objects().end(), has);
}

unsigned Profile::axes_from_product_code(std::uint32_t product_code) const {
    if (identity.axes_mask == 0) {
        return 1;
    }
    const unsigned n = (product_code & identity.axes_mask) >> identity.axes_shift;
    return std::clamp(n, 1U, static_cast<unsigned>(max_axes));
}

std::span<const Profile* const> all_profiles() {
    static const std::array<const Profile*, 4> profiles{&akd2g_profile(), &ds_bvs_profile(),
                                                        &fio_profile(), &generic_profile()};
    return profiles;
}

const Profile* find_profile(std::string_view name) {
    std::string key;
    for (char c : name) {
        if (c != '-' && c != '_' && c != ' ') {
            key.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
        }
    }
    if (key == "akd2g" || key == "kollmorgenakd2g") {
        return &akd2g_profile();
    }
    if (key == "dsbvs" || key == "dsbvm" || key == "bvs") {
        return &ds_bvs_profile();
    }
    if (key == "fio" || key == "kuhnkefio") {
        return &fio_profile();
    }
    if (key == "generic" || key == "cia402") {
        return &generic_profile();
    }
    return nullptr;
}

const Profile& profile_by_name(std::string_view name) {
    const Profile* p = find_profile(name);
    return p != nullptr ? *p : generic_profile();
}

const Profile* match_identity(std::uint32_t device_type, std::uint32_t vendor_id,
                              std::uint32_t product_code, std::string_view device_name) {
    if ((device_type & 0xFFFF) != 402) {
        return nullptr;
    }
    for (const Profile* p : all_profiles()) {
        const Identity& id = p->identity;
        if (p == &generic_profile()) {
            continue;
        }
        if ((device_type & id.device_type_mask) != (id.device_type & id.device_type_mask)) {
            continue;
        }
        if (id.vendor_id != 0) {
            if (vendor_id != id.vendor_id ||
                (product_code & id.product_code_mask) != (id.product_code & id.product_code_mask)) {
                continue;
            }
            return p;
        }
        if (!id.device_name.empty() && device_name.starts_with(id.device_name)) {
            return p;
        }
    }
    return &generic_profile();
}

namespace {

class ProfileEmcyText final : public emcy::IEmcyTextProvider {
public:
    explicit ProfileEmcyText(const Profile& p) : profile_(p) {}

    [[nodiscard]] std::optional<std::string>
    vendor_text(const emcy::EmcyMessage& m) const override {
        if (m.is_reset()) {
            return std::nullopt;
        }
        std::string out;
        // FIO: the error number travels in manufacturer byte 0 (1003h bits 31..24).
        if (!profile_.error_numbers.empty() && m.manufacturer[0] != 0) {
            if (const ErrorNumberRow* n = profile_.error_number(m.manufacturer[0])) {
                out = fmt::format("error number 0x{:02X}: {}", n->number, n->text);
            } else {
                out = fmt::format("error number 0x{:02X}", m.manufacturer[0]);
            }
        }
        if (const FaultRow* r = profile_.fault(m.error_code)) {
            const std::string text =
                r->number.empty() ? std::string(r->text) : fmt::format("{} {}", r->number, r->text);
            out = out.empty() ? text : fmt::format("{}; {}", out, text);
        }
        if (out.empty()) {
            return std::nullopt;
        }
        return out;
    }

private:
    const Profile& profile_;
};

Result<Value> make_value(DataType type, std::int64_t v) {
    if (is_unsigned_integer(type)) {
        return Value::from_uint(type, static_cast<std::uint64_t>(v));
    }
    if (is_real(type)) {
        return Value::from_double(type, static_cast<double>(v));
    }
    return Value::from_int(type, v);
}

} // namespace

std::shared_ptr<const emcy::IEmcyTextProvider> emcy_text_provider(const Profile& p) {
    return std::make_shared<ProfileEmcyText>(p);
}

std::vector<ObjectSpec> device_objects(const Profile& p, unsigned axis) {
    std::vector<ObjectSpec> out;
    const auto overridden = [&p](const ObjectSpec& s) {
        return std::any_of(
            p.object_overrides.begin(), p.object_overrides.end(),
            [&s](const ObjectSpec& o) { return o.index == s.index && o.subindex == s.subindex; });
    };
    for (const ObjectSpec& s : generic_objects()) {
        if (std::find(p.absent_objects.begin(), p.absent_objects.end(), s.index) !=
                p.absent_objects.end() ||
            overridden(s)) {
            continue;
        }
        out.push_back(s);
    }
    out.insert(out.end(), p.object_overrides.begin(), p.object_overrides.end());
    for (ObjectSpec& s : out) {
        s.index = p.axis_index(s.index, axis);
    }
    std::sort(out.begin(), out.end(), [](const ObjectSpec& a, const ObjectSpec& b) {
        return a.index != b.index ? a.index < b.index : a.subindex < b.subindex;
    });
    return out;
}

namespace {

SubObject make_sub(const ObjectSpec& s) {
    Value value = make_value(s.type, s.default_value).value_or(Value::zero(s.type));
    SubObject sub =
        SubObject::make(s.subindex, std::string(s.name), s.type, s.access, std::move(value), s.pdo);
    if (s.has_limits) {
        if (auto lo = make_value(s.type, s.low)) {
            sub.low_limit = *lo;
        }
        if (auto hi = make_value(s.type, s.high)) {
            sub.high_limit = *hi;
        }
    }
    return sub;
}

void add_u32(ObjectDictionary& od, std::uint16_t index, std::uint8_t subindex, std::string name,
             std::uint32_t v) {
    od.add_sub(index,
               SubObject::make(subindex, std::move(name), DataType::Unsigned32, Access::Ro,
                               *Value::from_uint(DataType::Unsigned32, v)),
               "Identity object");
}

/// CiA 301 error control objects of a CAN drive, so a bus file can name them in `writes:`:
/// 1001h, heartbeat consumer 1016h (one entry on the AKD2G and DS-BVS: bits 23..16 the producer,
/// 15..0 the time in ms), producer 1017h and, where the drive has it, error behaviour 1029h.
void add_can_error_control_objects(ObjectDictionary& od, const Profile& p) {
    const auto u = [](DataType t, std::uint64_t v) { return *Value::from_uint(t, v); };
    od.add_var(0x1001, "Error register", DataType::Unsigned8, Access::Ro,
               u(DataType::Unsigned8, 0));
    const DataType count_type = p.quirks.heartbeat_consumer_sub0_type;
    od.add_sub(
        0x1016,
        SubObject::make(0, "Highest sub-index supported", count_type, Access::Ro, u(count_type, 1)),
        "Consumer heartbeat time");
    od.add_sub(0x1016, SubObject::make(1, "Consumer heartbeat time", DataType::Unsigned32,
                                       Access::Rw, u(DataType::Unsigned32, 0)));
    od.find(0x1016)->code = ObjectCode::Array;
    od.add_var(0x1017, "Producer heartbeat time", DataType::Unsigned16, Access::Rw,
               u(DataType::Unsigned16, 0));
    add_error_behaviour_object(od, p);
}

} // namespace

void add_error_behaviour_object(ObjectDictionary& od, const Profile& p) {
    if (!p.quirks.error_behaviour_1029) {
        return;
    }
    const auto u8 = [](std::uint64_t v) { return *Value::from_uint(DataType::Unsigned8, v); };
    od.add_sub(
        0x1029,
        SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8, Access::Ro, u8(2)),
        "Error behaviour");
    // 0 pre-operational (if operational), 1 no state change, 2 stopped.
    for (const std::uint8_t sub : {std::uint8_t{1}, std::uint8_t{2}}) {
        auto e = SubObject::make(sub, sub == 1 ? "Communication error" : "Application error",
                                 DataType::Unsigned8, Access::Rw, u8(1));
        e.low_limit = u8(0);
        e.high_limit = u8(2);
        od.add_sub(0x1029, std::move(e));
    }
    od.find(0x1029)->code = ObjectCode::Array;
}

void build_device_dictionary(ObjectDictionary& od, const Profile& p, unsigned axes) {
    axes = std::clamp(axes, 1U, static_cast<unsigned>(p.max_axes));
    od.add_var(0x1000, "Device type", DataType::Unsigned32, Access::Ro,
               *Value::from_uint(DataType::Unsigned32, p.identity.device_type));
    od.add_sub(0x1018,
               SubObject::make(0, "Highest sub-index supported", DataType::Unsigned8, Access::Ro,
                               *Value::from_uint(DataType::Unsigned8, 4)),
               "Identity object");
    std::uint32_t product = p.identity.product_code;
    if (p.identity.axes_mask != 0) {
        product = (product & ~p.identity.axes_mask) |
                  ((axes << p.identity.axes_shift) & p.identity.axes_mask);
    }
    add_u32(od, 0x1018, 1, "Vendor-ID", p.identity.vendor_id);
    add_u32(od, 0x1018, 2, "Product code", product);
    add_u32(od, 0x1018, 3, "Revision number", 0);
    add_u32(od, 0x1018, 4, "Serial number", 0);
    if (auto* id = od.find(0x1018)) {
        id->code = ObjectCode::Record;
    }
    if (p.quirks.canopen) {
        add_can_error_control_objects(od, p);
    }

    for (unsigned axis = 1; axis <= axes; ++axis) {
        for (const ObjectSpec& s : device_objects(p, axis)) {
            add_object(od, s);
        }
    }
}

namespace {
/// The name add_object gives a sub 0 it maintains as "highest sub-index supported".
constexpr const char* kHighestSubName = "Highest sub-index supported";
} // namespace

void add_object(ObjectDictionary& od, const ObjectSpec& s) {
    if (!s.record) {
        od.add_var(s.index, std::string(s.name), s.type, s.access, make_sub(s).value, s.pdo);
        if (auto* sub = od.find(s.index, 0)) {
            *sub = make_sub(s);
        }
        return;
    }
    if (s.subindex == 0) {
        // An explicit sub 0 of a record (a count the manual gives, e.g. DS-BVS 4702h:00 =
        // number of entries): kept as described, the other subs leave it alone.
        od.add_sub(s.index, make_sub(s), std::string(s.name));
        return;
    }
    if (od.find(s.index, 0) == nullptr) {
        od.add_sub(s.index,
                   SubObject::make(0, kHighestSubName, DataType::Unsigned8, Access::Ro,
                                   *Value::from_uint(DataType::Unsigned8, 0)),
                   std::string(s.name));
    }
    od.add_sub(s.index, make_sub(s));
    // Sub 0 follows the highest sub-index unless the profile describes sub 0 itself.
    if (auto* sub0 = od.find(s.index, 0); sub0 != nullptr && sub0->name == kHighestSubName) {
        const std::uint8_t highest =
            std::max(od.get<std::uint8_t>(s.index, 0).value_or(0), s.subindex);
        *sub0 = SubObject::make(0, kHighestSubName, DataType::Unsigned8, Access::Ro,
                                *Value::from_uint(DataType::Unsigned8, highest));
    }
}

std::uint32_t mapping_value(const Profile& p, const PdoEntry& e, unsigned axis) {
    return (static_cast<std::uint32_t>(p.axis_index(e.index, axis)) << 16) |
           (static_cast<std::uint32_t>(e.subindex) << 8) | e.bits;
}

} // namespace codrive::drives
