// SPDX-License-Identifier: Apache-2.0
// The slave side of FoE (file access over EtherCAT, ETG.1000.6 §5.7): a file store per slave
// answering RRQ/WRQ/DATA/ACK/ERR, optionally backed by a directory.
#pragma once

#include <codrive/ethercat/al_state.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace codrive::sim::ecat {

class FoeServer {
public:
    /// `rx_mailbox`/`tx_mailbox`: the slave's SM0/SM1 sizes (bound every DATA in each
    /// direction). `write_in_op`: whether files may be written in OP (the AKD2G takes its
    /// parameter file in INIT, PRE-OP or SAFE-OP only: manual §2.3.3.4 step 3).
    FoeServer(std::size_t rx_mailbox, std::size_t tx_mailbox, bool write_in_op = false);

    /// Handles one FoE payload (FoE header first); returns the FoE answer, or nothing (an ERR
    /// from the master, the final ACK of a read).
    std::optional<std::vector<std::uint8_t>> handle(std::span<const std::uint8_t> payload,
                                                    ethercat::AlState state);
    /// Drops a transfer in progress (the ESC went back to INIT, mailboxes cleared).
    void reset();

    /// Files kept in memory, by name.
    [[nodiscard]] std::map<std::string, std::vector<std::uint8_t>>& files() { return files_; }
    /// Reads fall back to `dir`/NAME and written files are stored there too (plain names only:
    /// a name with '/' or ".." is refused with access denied).
    void set_directory(std::string dir) { dir_ = std::move(dir); }
    /// Test hook: answer the next `n` DATA of a write with BUSY (the master sends them again).
    void busy_next(int n) { busy_left_ = n; }
    /// Largest file a write may store (ERR 0x8003 disk full beyond it).
    void set_max_file(std::size_t bytes) { max_file_ = bytes; }
    [[nodiscard]] std::uint64_t busy_sent() const { return busy_sent_; }
    [[nodiscard]] std::uint64_t errors_sent() const { return errors_sent_; }

private:
    std::vector<std::uint8_t> error(std::uint32_t code);
    std::vector<std::uint8_t> next_data();
    std::optional<std::vector<std::uint8_t>> load(const std::string& name) const;
    std::uint32_t store(const std::string& name, std::vector<std::uint8_t> data);
    [[nodiscard]] bool plain_name(const std::string& name) const;

    enum class Mode : std::uint8_t { Idle, Reading, Writing };
    std::size_t rx_max_; ///< data bytes per DATA the master sends
    std::size_t tx_max_; ///< data bytes per DATA this slave sends
    bool write_in_op_;
    std::map<std::string, std::vector<std::uint8_t>> files_;
    std::string dir_;
    std::size_t max_file_ = 4U * 1024U * 1024U;
    Mode mode_ = Mode::Idle;
    std::string name_;
    std::vector<std::uint8_t> buffer_;
    std::size_t offset_ = 0;   ///< read: bytes sent so far
    std::uint32_t packet_ = 0; ///< read: last DATA sent; write: last DATA taken
    bool last_sent_ = false;
    int busy_left_ = 0;
    std::uint64_t busy_sent_ = 0;
    std::uint64_t errors_sent_ = 0;
};

} // namespace codrive::sim::ecat
