// SPDX-License-Identifier: Apache-2.0
// Slave-side FoE (ETG.1000.6 §5.7): RRQ answered with DATA 1.. (each up to the SM1 mailbox, a
// shorter one ends the file), WRQ with ACK 0 and every DATA with its ACK, ERR for unknown files,
// wrong packet numbers and requests out of sequence.
#include <codrive/sim/ecat/foe_server.hpp>

#include <codrive/ethercat/foe.hpp>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

namespace codrive::sim::ecat {

using namespace codrive::ethercat;

FoeServer::FoeServer(std::size_t rx_mailbox, std::size_t tx_mailbox, bool write_in_op)
    : rx_max_(foe_max_data(rx_mailbox)), tx_max_(foe_max_data(tx_mailbox)),
      write_in_op_(write_in_op) {}

void FoeServer::reset() {
    mode_ = Mode::Idle;
    buffer_.clear();
    offset_ = 0;
    packet_ = 0;
    last_sent_ = false;
}

std::vector<std::uint8_t> FoeServer::error(std::uint32_t code) {
    reset();
    ++errors_sent_;
    const char* text = foe_error_text(code);
    std::vector<std::uint8_t> out;
    encode_foe(out, FoeOpcode::Error, code,
               std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text),
                                             std::strlen(text)));
    return out;
}

bool FoeServer::plain_name(const std::string& name) const {
    return !name.empty() && name.find('/') == std::string::npos && name != "." && name != "..";
}

std::optional<std::vector<std::uint8_t>> FoeServer::load(const std::string& name) const {
    if (const auto it = files_.find(name); it != files_.end()) {
        return it->second;
    }
    if (dir_.empty() || !plain_name(name)) {
        return std::nullopt;
    }
    std::ifstream in(dir_ + "/" + name, std::ios::binary);
    if (!in) {
        return std::nullopt;
    }
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

std::uint32_t FoeServer::store(const std::string& name, std::vector<std::uint8_t> data) {
    if (!dir_.empty()) {
        const std::string path = dir_ + "/" + name;
        const std::string tmp = path + ".foe-tmp";
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data.data()),
                  static_cast<std::streamsize>(data.size()));
        out.close();
        if (!out || std::rename(tmp.c_str(), path.c_str()) != 0) {
            std::remove(tmp.c_str());
            return foe_error::kDiskFull;
        }
    }
    files_[name] = std::move(data);
    return 0;
}

std::vector<std::uint8_t> FoeServer::next_data() {
    const std::size_t n = std::min(tx_max_, buffer_.size() - offset_);
    ++packet_;
    std::vector<std::uint8_t> out;
    encode_foe(out, FoeOpcode::Data, packet_,
               std::span<const std::uint8_t>(buffer_).subspan(offset_, n));
    offset_ += n;
    last_sent_ = n < tx_max_; // a file that fills its last DATA exactly ends with an empty one
    return out;
}

std::optional<std::vector<std::uint8_t>> FoeServer::handle(std::span<const std::uint8_t> payload,
                                                           AlState state) {
    const auto m = decode_foe(payload);
    if (!m) {
        return error(foe_error::kIllegal);
    }
    switch (m->opcode) {
    case FoeOpcode::ReadRequest: {
        // A new request ends whatever ran before (the master gave up on it).
        reset();
        name_.assign(m->body.begin(), m->body.end());
        name_ = name_.substr(0, name_.find('\0'));
        auto data = load(name_);
        if (!data) {
            return error(foe_error::kNotFound);
        }
        buffer_ = std::move(*data);
        mode_ = Mode::Reading;
        return next_data();
    }
    case FoeOpcode::WriteRequest: {
        reset();
        name_.assign(m->body.begin(), m->body.end());
        name_ = name_.substr(0, name_.find('\0'));
        if (!plain_name(name_)) {
            return error(foe_error::kAccessDenied);
        }
        if (state == AlState::Op && !write_in_op_) {
            return error(foe_error::kAccessDenied);
        }
        mode_ = Mode::Writing;
        std::vector<std::uint8_t> ack;
        encode_foe(ack, FoeOpcode::Ack, 0);
        return ack;
    }
    case FoeOpcode::Ack:
        if (mode_ != Mode::Reading) {
            return error(foe_error::kIllegal);
        }
        if (m->value != packet_) {
            return error(foe_error::kPacketNumberWrong);
        }
        if (last_sent_) {
            reset(); // the ACK of the last DATA: the read is complete
            return std::nullopt;
        }
        return next_data();
    case FoeOpcode::Data: {
        if (mode_ != Mode::Writing) {
            return error(foe_error::kIllegal);
        }
        if (m->value != packet_ + 1) {
            return error(foe_error::kPacketNumberWrong);
        }
        if (busy_left_ > 0) {
            // Not taken: the master sends this DATA again (ETG.1000.6 §5.7, BUSY).
            --busy_left_;
            ++busy_sent_;
            std::vector<std::uint8_t> busy;
            const char* text = "busy";
            encode_foe(busy, FoeOpcode::Busy,
                       foe_busy_value(static_cast<std::uint16_t>(packet_), 0),
                       std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text),
                                                     std::strlen(text)));
            return busy;
        }
        if (buffer_.size() + m->body.size() > max_file_) {
            return error(foe_error::kDiskFull);
        }
        buffer_.insert(buffer_.end(), m->body.begin(), m->body.end());
        packet_ = m->value;
        std::vector<std::uint8_t> ack;
        encode_foe(ack, FoeOpcode::Ack, packet_);
        if (m->body.size() < rx_max_) {
            // The last DATA: the file is complete.
            if (const std::uint32_t e = store(name_, std::move(buffer_)); e != 0) {
                return error(e);
            }
            reset();
        }
        return ack;
    }
    case FoeOpcode::Error:
        reset(); // the master ended the transfer; no answer (ETG.1000.6 §5.7)
        return std::nullopt;
    case FoeOpcode::Busy:
        return error(foe_error::kIllegal);
    }
    return error(foe_error::kIllegal);
}

} // namespace codrive::sim::ecat
