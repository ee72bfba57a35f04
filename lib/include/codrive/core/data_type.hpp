// SPDX-License-Identifier: Apache-2.0
// CiA 301 static data types (§7.1, table 44), object codes and access types.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace codrive {

/// CiA 301 data type indexes (the value is the object index of the DEFTYPE).
enum class DataType : std::uint16_t {
    Boolean = 0x0001,
    Integer8 = 0x0002,
    Integer16 = 0x0003,
    Integer32 = 0x0004,
    Unsigned8 = 0x0005,
    Unsigned16 = 0x0006,
    Unsigned32 = 0x0007,
    Real32 = 0x0008,
    VisibleString = 0x0009,
    OctetString = 0x000A,
    UnicodeString = 0x000B,
    TimeOfDay = 0x000C,
    TimeDifference = 0x000D,
    Domain = 0x000F,
    Integer24 = 0x0010,
    Real64 = 0x0011,
    Integer40 = 0x0012,
    Integer48 = 0x0013,
    Integer56 = 0x0014,
    Integer64 = 0x0015,
    Unsigned24 = 0x0016,
    Unsigned40 = 0x0018,
    Unsigned48 = 0x0019,
    Unsigned56 = 0x001A,
    Unsigned64 = 0x001B,
};

/// Size in bytes of a fixed-size type; 0 for strings and domains (variable size).
[[nodiscard]] std::size_t data_type_size(DataType t);
[[nodiscard]] bool is_signed_integer(DataType t);
[[nodiscard]] bool is_unsigned_integer(DataType t); ///< includes BOOLEAN
[[nodiscard]] bool is_real(DataType t);
[[nodiscard]] bool is_variable_size(DataType t); ///< strings and DOMAIN
/// "UNSIGNED32", "VISIBLE_STRING", ...
[[nodiscard]] std::string_view to_string(DataType t);
/// The DataType for a CiA 301 data type index, or nullopt if it is not a basic type.
[[nodiscard]] std::optional<DataType> data_type_from_index(std::uint16_t index);
/// Parses names used by tools and files: "u32", "UNSIGNED32", "i16", "f32", "str", "domain".
[[nodiscard]] std::optional<DataType> data_type_from_name(std::string_view name);

/// CiA 301 object codes (EDS ObjectType).
enum class ObjectCode : std::uint8_t {
    Null = 0x0,
    Domain = 0x2,
    Deftype = 0x5,
    Defstruct = 0x6,
    Var = 0x7,
    Array = 0x8,
    Record = 0x9,
};
[[nodiscard]] std::string_view to_string(ObjectCode c);

/// Access types (CiA 306 AccessType): rww is writable by RPDO, rwr readable by TPDO.
enum class Access : std::uint8_t { Ro, Wo, Rw, Rwr, Rww, Const };
[[nodiscard]] std::string_view to_string(Access a); ///< "ro", "wo", "rw", "rwr", "rww", "const"
[[nodiscard]] std::optional<Access> access_from_string(std::string_view s);
[[nodiscard]] constexpr bool readable(Access a) {
    return a != Access::Wo;
}
[[nodiscard]] constexpr bool writable(Access a) {
    return a != Access::Ro && a != Access::Const;
}

} // namespace codrive
