// SPDX-License-Identifier: Apache-2.0
// Reads a node's PDO configuration (1400h–1BFFh) over SDO into a readable description.
#pragma once

#include <codrive/core/object_dictionary.hpp>
#include <codrive/pdo/error.hpp>
#include <codrive/pdo/types.hpp>
#include <codrive/sdo/client.hpp>

#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace codrive::pdo {

/// A node's PDOs as read back from it.
struct NodePdoConfiguration {
    NodeId node = 0;
    std::vector<PdoConfig> pdos; ///< RPDOs then TPDOs, those that exist on the node
    /// Optional sub-indexes the node did not have (e.g. "TPDO1 has no sub-index 06h").
    std::vector<std::string> notes;

    [[nodiscard]] const PdoConfig* find(PdoDir dir, unsigned number) const;
    /// A table, one PDO per line: name, COB-ID, valid, transmission type, inhibit, event timer,
    /// bytes and the entries (with object names from `od` where given):
    ///   PDO    COB-ID  valid  transmission          inhibit  timer  bytes  mapping
    ///   TPDO1  0x183   yes    1 (every SYNC)        0 µs     0 ms   6      0x6041:00/16 ...
    [[nodiscard]] std::string to_string(const ObjectDictionary* od = nullptr) const;
};

/// Reads PDOs 1..rpdos and 1..tpdos of one node. A PDO whose communication object does not
/// exist (abort 0x06020000) is left out; missing optional sub-indexes (03h, 05h, 06h) become
/// notes. Any other failure ends the read with SdoFailed and the SDO error's sentence.
class PdoReader {
public:
    using Done = std::function<void(PdoResult<NodePdoConfiguration>)>;

    explicit PdoReader(sdo::SdoClient& client);
    ~PdoReader();
    PdoReader(const PdoReader&) = delete;
    PdoReader& operator=(const PdoReader&) = delete;

    /// False (and `done` is not called) if a read is already running.
    bool read(unsigned rpdos, unsigned tpdos, Done done);
    [[nodiscard]] bool busy() const { return running_; }

private:
    struct Step {
        std::uint16_t index;
        std::uint8_t subindex;
        bool optional; ///< NoObject/NoSubindex are tolerated
        std::function<void(const sdo::SdoResult<sdo::Bytes>&)> handle;
    };
    void queue_pdo(PdoDir dir, unsigned number);
    void next();
    void finish(PdoResult<NodePdoConfiguration> r);

    sdo::SdoClient& client_;
    std::deque<Step> steps_;
    NodePdoConfiguration result_;
    bool running_ = false;
    Done done_;
    std::shared_ptr<bool> alive_;
};

} // namespace codrive::pdo
