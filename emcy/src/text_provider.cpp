// SPDX-License-Identifier: Apache-2.0
// Vendor EMCY text providers: tables and chains.
#include <codrive/emcy/text_provider.hpp>

#include <bit>

namespace codrive::emcy {

const EmcyTextEntry* EmcyTextTable::find(const EmcyMessage& m) const {
    const EmcyTextEntry* best = nullptr;
    int best_score = -1;
    for (const auto& row : rows_) {
        if ((m.error_code & row.code_mask) != (row.code & row.code_mask)) {
            continue;
        }
        if (row.mfr_index >= 0) {
            const auto index = static_cast<std::size_t>(static_cast<unsigned char>(row.mfr_index));
            if (index >= m.manufacturer.size() || m.manufacturer[index] != row.mfr_value) {
                continue;
            }
        }
        const int score = (row.mfr_index >= 0 ? 100 : 0) + std::popcount(row.code_mask);
        if (score > best_score) {
            best = &row;
            best_score = score;
        }
    }
    return best;
}

std::optional<std::string> EmcyTextTable::vendor_text(const EmcyMessage& m) const {
    if (const EmcyTextEntry* row = find(m)) {
        return std::string(row->text);
    }
    return std::nullopt;
}

std::optional<std::string> EmcyTextChain::vendor_text(const EmcyMessage& m) const {
    std::optional<std::string> out;
    for (const auto* p : providers_) {
        if (p == nullptr) {
            continue;
        }
        auto t = p->vendor_text(m);
        if (!t || t->empty()) {
            continue;
        }
        if (out) {
            *out += "; ";
            *out += *t;
        } else {
            out = std::move(t);
        }
    }
    return out;
}

} // namespace codrive::emcy
