// SPDX-License-Identifier: Apache-2.0
// The hook through which drive profiles add vendor text to EMCY messages.
#pragma once

#include <codrive/emcy/message.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace codrive::emcy {

/// Supplies vendor text for an EMCY. Vendor meaning may depend on the manufacturer bytes, not
/// only on the code: the Kuhnke FIO puts an "error number" in manufacturer byte 0 (1003h bits
/// 31..24), the AKD2G maps each code to one fault/warning number, DS-BVS uses the 603Fh list.
class IEmcyTextProvider {
public:
    virtual ~IEmcyTextProvider() = default;
    /// Text for this message, or nullopt to use the standard text only.
    [[nodiscard]] virtual std::optional<std::string> vendor_text(const EmcyMessage& m) const = 0;
};

/// One row of a vendor table. A row matches when (code & code_mask) == (row.code & code_mask)
/// and, if mfr_index >= 0, manufacturer[mfr_index] == mfr_value.
struct EmcyTextEntry {
    std::uint16_t code = 0;
    std::string_view text;
    std::uint16_t code_mask = 0xFFFF; ///< 0 matches any code (e.g. FIO error numbers alone)
    std::int8_t mfr_index = -1;       ///< manufacturer byte 0..4 to compare, -1 = none
    std::uint8_t mfr_value = 0;
};

/// A table provider. The most specific matching row wins: a row that also matches a
/// manufacturer byte beats one that does not; then the one with more code-mask bits; then the
/// earlier row. The rows (and the strings they view) must outlive the table — static tables.
class EmcyTextTable final : public IEmcyTextProvider {
public:
    explicit EmcyTextTable(std::span<const EmcyTextEntry> rows) : rows_(rows) {}
    [[nodiscard]] std::optional<std::string> vendor_text(const EmcyMessage& m) const override;
    /// The best row, or nullptr.
    [[nodiscard]] const EmcyTextEntry* find(const EmcyMessage& m) const;

private:
    std::span<const EmcyTextEntry> rows_;
};

/// Adapts a function (e.g. a lambda composing several tables).
class EmcyTextFunction final : public IEmcyTextProvider {
public:
    using Fn = std::function<std::optional<std::string>(const EmcyMessage&)>;
    explicit EmcyTextFunction(Fn fn) : fn_(std::move(fn)) {}
    [[nodiscard]] std::optional<std::string> vendor_text(const EmcyMessage& m) const override {
        return fn_ ? fn_(m) : std::nullopt;
    }

private:
    Fn fn_;
};

/// Joins the texts of several providers with "; " (e.g. FIO: code table + error-number table).
class EmcyTextChain final : public IEmcyTextProvider {
public:
    explicit EmcyTextChain(std::vector<const IEmcyTextProvider*> providers)
        : providers_(std::move(providers)) {}
    [[nodiscard]] std::optional<std::string> vendor_text(const EmcyMessage& m) const override;

private:
    std::vector<const IEmcyTextProvider*> providers_;
};

} // namespace codrive::emcy
