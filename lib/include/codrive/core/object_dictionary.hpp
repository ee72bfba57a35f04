// SPDX-License-Identifier: Apache-2.0
// The object dictionary model (CiA 301 §7.4): objects, sub-objects, access checks and hooks.
#pragma once

#include <codrive/core/data_type.hpp>
#include <codrive/core/error.hpp>
#include <codrive/core/sdo_abort.hpp>
#include <codrive/core/value.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace codrive {

/// Where an entry may be mapped. CiA 306 "PDOMapping=1" plus the access type decide the direction.
enum class PdoDir : std::uint8_t { Rpdo, Tpdo };

/// One sub-object (for a VAR, the object itself at sub-index 0).
struct SubObject {
    std::uint8_t subindex = 0;
    std::string name;
    DataType type = DataType::Unsigned8;
    Access access = Access::Ro;
    bool pdo_mappable = false;
    Value value; ///< current value
    std::optional<Value> default_value;
    std::optional<Value> low_limit;
    std::optional<Value> high_limit;
    std::string default_text;    ///< DefaultValue as written in an EDS (may use $NODEID)
    std::string parameter_text;  ///< DCF ParameterValue as written, if any
    std::uint32_t obj_flags = 0; ///< CiA 306 ObjFlags

    /// A sub-object whose current and default value is `value`.
    static SubObject make(std::uint8_t subindex, std::string name, DataType type, Access access,
                          Value value, bool pdo_mappable = false) {
        SubObject s;
        s.subindex = subindex;
        s.name = std::move(name);
        s.type = type;
        s.access = access;
        s.pdo_mappable = pdo_mappable;
        s.default_value = value;
        s.value = std::move(value);
        return s;
    }

    /// Mappable into a PDO in this direction (rwr → TPDO only, rww → RPDO only).
    [[nodiscard]] bool mappable(PdoDir dir) const;
    /// Bit length of the value when mapped (fixed-size types only).
    [[nodiscard]] std::size_t bit_length() const { return data_type_size(type) * 8; }
};

/// One object (index).
struct Object {
    std::uint16_t index = 0;
    std::string name;
    ObjectCode code = ObjectCode::Var;
    std::map<std::uint8_t, SubObject> subs; ///< VAR: exactly sub 0
    std::uint32_t obj_flags = 0;

    [[nodiscard]] const SubObject* find(std::uint8_t subindex) const;
    [[nodiscard]] SubObject* find(std::uint8_t subindex);
};

/// Called by `write()` after the checks pass and before the value is stored; returning an abort
/// code vetoes the write (e.g. "PDO mapping only in pre-operational").
using WriteHook = std::function<tl::expected<void, SdoAbort>(
    std::uint16_t index, std::uint8_t subindex, std::span<const std::uint8_t> data)>;
/// Called before a read through `read()`; may refresh the value (e.g. a live statusword).
using ReadHook = std::function<void(std::uint16_t index, std::uint8_t subindex, SubObject& sub)>;

/// An object dictionary. Values are stored in place; `read`/`write` enforce access, length and
/// range the way an SDO server must (the returned SdoAbort is what goes on the wire).
class ObjectDictionary {
public:
    /// Adds or replaces an object.
    Object& insert(Object obj);
    /// Adds a VAR object with one value.
    Object& add_var(std::uint16_t index, std::string name, DataType type, Access access,
                    Value value, bool pdo_mappable = false);
    /// Adds sub-object `sub` to an existing ARRAY/RECORD (created as RECORD if missing).
    SubObject& add_sub(std::uint16_t index, SubObject sub, std::string object_name = {});

    [[nodiscard]] const Object* find(std::uint16_t index) const;
    [[nodiscard]] Object* find(std::uint16_t index);
    [[nodiscard]] const SubObject* find(std::uint16_t index, std::uint8_t subindex) const;
    [[nodiscard]] SubObject* find(std::uint16_t index, std::uint8_t subindex);

    /// Reads the bytes of a sub-object as an SDO server would: NoObject, NoSubindex, WriteOnly.
    [[nodiscard]] tl::expected<std::span<const std::uint8_t>, SdoAbort> read(std::uint16_t index,
                                                                             std::uint8_t subindex);

    /// Checks a write without performing it: NoObject, NoSubindex, ReadOnly, LengthTooHigh/Low,
    /// ValueTooHigh/Low.
    [[nodiscard]] tl::expected<void, SdoAbort>
    check_write(std::uint16_t index, std::uint8_t subindex,
                std::span<const std::uint8_t> data) const;

    /// Checks then writes, then runs the write hooks. `force` skips the access check (local
    /// application writes to read-only objects).
    tl::expected<void, SdoAbort> write(std::uint16_t index, std::uint8_t subindex,
                                       std::span<const std::uint8_t> data, bool force = false);

    /// Typed local access (no access check) for application code and simulators.
    template <typename T>
    [[nodiscard]] std::optional<T> get(std::uint16_t index, std::uint8_t subindex) const {
        const SubObject* s = find(index, subindex);
        if (s == nullptr || s->value.size() < sizeof(T)) {
            return std::nullopt;
        }
        return get_le<T>(s->value.bytes().data());
    }
    template <typename T>
    bool set(std::uint16_t index, std::uint8_t subindex, T v) {
        SubObject* s = find(index, subindex);
        if (s == nullptr) {
            return false;
        }
        auto& b = s->value.mutable_bytes();
        b.resize(sizeof(T));
        put_le<T>(b.data(), v);
        return true;
    }

    /// Hook for every write (in addition to per-index hooks).
    void on_write(WriteHook hook) { global_write_hook_ = std::move(hook); }
    void on_write(std::uint16_t index, WriteHook hook) { write_hooks_[index] = std::move(hook); }
    void on_read(std::uint16_t index, ReadHook hook) { read_hooks_[index] = std::move(hook); }

    [[nodiscard]] const std::map<std::uint16_t, Object>& objects() const { return objects_; }
    [[nodiscard]] std::size_t size() const { return objects_.size(); }
    /// Object or sub-object name for messages: "Statusword", "Identity object.Vendor-ID", or "".
    [[nodiscard]] std::string name_of(std::uint16_t index, std::uint8_t subindex) const;

private:
    std::map<std::uint16_t, Object> objects_;
    std::map<std::uint16_t, WriteHook> write_hooks_;
    std::map<std::uint16_t, ReadHook> read_hooks_;
    WriteHook global_write_hook_;
};

} // namespace codrive
