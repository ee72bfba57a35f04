// SPDX-License-Identifier: Apache-2.0
// Sizes and names of the CiA 301 data types, object codes and access types.
#include <codrive/core/data_type.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <string>

namespace codrive {
namespace {

struct TypeRow {
    DataType type;
    std::size_t size;
    std::string_view name;
    std::string_view short_name;
};

constexpr std::array kTypes{
    TypeRow{DataType::Boolean, 1, "BOOLEAN", "bool"},
    TypeRow{DataType::Integer8, 1, "INTEGER8", "i8"},
    TypeRow{DataType::Integer16, 2, "INTEGER16", "i16"},
    TypeRow{DataType::Integer32, 4, "INTEGER32", "i32"},
    TypeRow{DataType::Unsigned8, 1, "UNSIGNED8", "u8"},
    TypeRow{DataType::Unsigned16, 2, "UNSIGNED16", "u16"},
    TypeRow{DataType::Unsigned32, 4, "UNSIGNED32", "u32"},
    TypeRow{DataType::Real32, 4, "REAL32", "f32"},
    TypeRow{DataType::VisibleString, 0, "VISIBLE_STRING", "str"},
    TypeRow{DataType::OctetString, 0, "OCTET_STRING", "hex"},
    TypeRow{DataType::UnicodeString, 0, "UNICODE_STRING", "ustr"},
    TypeRow{DataType::TimeOfDay, 6, "TIME_OF_DAY", "tod"},
    TypeRow{DataType::TimeDifference, 6, "TIME_DIFFERENCE", "tdiff"},
    TypeRow{DataType::Domain, 0, "DOMAIN", "domain"},
    TypeRow{DataType::Integer24, 3, "INTEGER24", "i24"},
    TypeRow{DataType::Real64, 8, "REAL64", "f64"},
    TypeRow{DataType::Integer40, 5, "INTEGER40", "i40"},
    TypeRow{DataType::Integer48, 6, "INTEGER48", "i48"},
    TypeRow{DataType::Integer56, 7, "INTEGER56", "i56"},
    TypeRow{DataType::Integer64, 8, "INTEGER64", "i64"},
    TypeRow{DataType::Unsigned24, 3, "UNSIGNED24", "u24"},
    TypeRow{DataType::Unsigned40, 5, "UNSIGNED40", "u40"},
    TypeRow{DataType::Unsigned48, 6, "UNSIGNED48", "u48"},
    TypeRow{DataType::Unsigned56, 7, "UNSIGNED56", "u56"},
    TypeRow{DataType::Unsigned64, 8, "UNSIGNED64", "u64"},
};

const TypeRow* row(DataType t) {
    for (const auto& r : kTypes) {
        if (r.type == t) {
            return &r;
        }
    }
    return nullptr;
}

bool iequals(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

} // namespace

std::size_t data_type_size(DataType t) {
    const TypeRow* r = row(t);
    return r != nullptr ? r->size : 0;
}

bool is_signed_integer(DataType t) {
    switch (t) {
    case DataType::Integer8:
    case DataType::Integer16:
    case DataType::Integer24:
    case DataType::Integer32:
    case DataType::Integer40:
    case DataType::Integer48:
    case DataType::Integer56:
    case DataType::Integer64:
        return true;
    default:
        return false;
    }
}

bool is_unsigned_integer(DataType t) {
    switch (t) {
    case DataType::Boolean:
    case DataType::Unsigned8:
    case DataType::Unsigned16:
    case DataType::Unsigned24:
    case DataType::Unsigned32:
    case DataType::Unsigned40:
    case DataType::Unsigned48:
    case DataType::Unsigned56:
    case DataType::Unsigned64:
        return true;
    default:
        return false;
    }
}

bool is_real(DataType t) {
    return t == DataType::Real32 || t == DataType::Real64;
}

bool is_variable_size(DataType t) {
    return data_type_size(t) == 0;
}

std::string_view to_string(DataType t) {
    const TypeRow* r = row(t);
    return r != nullptr ? r->name : "UNKNOWN_TYPE";
}

std::optional<DataType> data_type_from_index(std::uint16_t index) {
    const TypeRow* r = row(static_cast<DataType>(index));
    if (r == nullptr) {
        return std::nullopt;
    }
    return r->type;
}

std::optional<DataType> data_type_from_name(std::string_view name) {
    for (const auto& r : kTypes) {
        if (iequals(name, r.name) || iequals(name, r.short_name)) {
            return r.type;
        }
    }
    if (iequals(name, "string")) {
        return DataType::VisibleString;
    }
    if (iequals(name, "bytes") || iequals(name, "octets")) {
        return DataType::OctetString;
    }
    return std::nullopt;
}

std::string_view to_string(ObjectCode c) {
    switch (c) {
    case ObjectCode::Null:
        return "NULL";
    case ObjectCode::Domain:
        return "DOMAIN";
    case ObjectCode::Deftype:
        return "DEFTYPE";
    case ObjectCode::Defstruct:
        return "DEFSTRUCT";
    case ObjectCode::Var:
        return "VAR";
    case ObjectCode::Array:
        return "ARRAY";
    case ObjectCode::Record:
        return "RECORD";
    }
    return "?";
}

std::string_view to_string(Access a) {
    switch (a) {
    case Access::Ro:
        return "ro";
    case Access::Wo:
        return "wo";
    case Access::Rw:
        return "rw";
    case Access::Rwr:
        return "rwr";
    case Access::Rww:
        return "rww";
    case Access::Const:
        return "const";
    }
    return "?";
}

std::optional<Access> access_from_string(std::string_view s) {
    // Trim surrounding white space: vendor files write "rw " and " ro".
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0) {
        s.remove_prefix(1);
    }
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0) {
        s.remove_suffix(1);
    }
    for (Access a : {Access::Ro, Access::Wo, Access::Rw, Access::Rwr, Access::Rww, Access::Const}) {
        if (iequals(s, to_string(a))) {
            return a;
        }
    }
    return std::nullopt;
}

} // namespace codrive
