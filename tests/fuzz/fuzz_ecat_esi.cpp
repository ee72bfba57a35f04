// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the ESI reader (ETG.2000 XML) must survive any input: an EsiFile or one
// `file:line:` sentence, never a crash, and every lookup on what it read must hold.
#include <codrive/ethercat/esi.hpp>
#include <codrive/ethercat/esi_pdos.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const auto esi = codrive::ethercat::parse_esi(text, "fuzz.xml");
    if (!esi) {
        // A finding always names the file and a line.
        if (esi.error().rfind("fuzz.xml:", 0) != 0) {
            std::abort();
        }
        return 0;
    }
    for (const auto& d : esi->devices) {
        if (esi->match(esi->vendor_id, d.product_code, d.revision) == nullptr) {
            std::abort(); // a device the file describes is found by its own identity
        }
        for (const auto& o : d.objects) {
            for (const auto& e : o.entries) {
                if (d.entry(o.index, e.subindex) == nullptr) {
                    std::abort();
                }
            }
        }
        (void)codrive::ethercat::esi_default_pdos(d);
        (void)d.describe();
    }
    if (esi->mismatch(0, 0, 0).empty()) {
        std::abort();
    }
    return 0;
}
