// SPDX-License-Identifier: Apache-2.0
// FoE read and write as step machines (ETG.1000.6 §5.7): one FoE message out, one in per step,
// carried by the master's mailbox channel like the CoE transfers. Read: RRQ, DATA n / ACK n until
// a DATA shorter than the mailbox allows. Write: WRQ, ACK 0, DATA n / ACK n, the same DATA again
// after a BUSY. A protocol violation ends the transfer with an ERR to the slave.
#include "foe_transfer.hpp"

#include <codrive/ethercat/error.hpp>

#include <fmt/format.h>

#include <algorithm>

namespace codrive::ethercat::detail {
namespace {

const char* opcode_name(FoeOpcode op) {
    switch (op) {
    case FoeOpcode::ReadRequest:
        return "RRQ";
    case FoeOpcode::WriteRequest:
        return "WRQ";
    case FoeOpcode::Data:
        return "DATA";
    case FoeOpcode::Ack:
        return "ACK";
    case FoeOpcode::Error:
        return "ERR";
    case FoeOpcode::Busy:
        return "BUSY";
    }
    return "?";
}

/// The slave's error or busy text, printable characters only, without the padding zeros.
std::string slave_text(std::span<const std::uint8_t> body) {
    std::string t;
    for (const auto c : body) {
        if (c == 0) {
            break;
        }
        t.push_back(c >= 0x20 && c < 0x7F ? static_cast<char>(c) : '?');
    }
    return t;
}

std::span<const std::uint8_t> bytes_of(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

class FoeTransfer : public CoeTransfer {
public:
    FoeTransfer(std::string name, FoeOptions options, std::size_t mailbox, IClock& clock)
        : name_(std::move(name)), options_(std::move(options)), max_(foe_max_data(mailbox)),
          clock_(clock) {}
    [[nodiscard]] CoeService service() const override { return CoeService::SdoResponse; }
    [[nodiscard]] MailboxType mailbox_type() const override { return MailboxType::Foe; }

    Step on_reply(std::span<const std::uint8_t> payload,
                  std::vector<std::uint8_t>& request) override {
        const auto m = decode_foe(payload);
        if (!m) {
            return abandon(request, foe_error::kIllegal, "the slave's FoE message is malformed");
        }
        if (m->opcode == FoeOpcode::Error) {
            outcome.error = make_foe_error(m->value);
            const std::string text = slave_text(m->body);
            outcome.sentence = fmt::format("{}: {}: the slave answered error 0x{:04X} ({}){}",
                                           label, what, m->value, foe_error_text(m->value),
                                           text.empty() ? "" : fmt::format(": \"{}\"", text));
            return Step::Failed;
        }
        if (m->opcode != FoeOpcode::Busy) {
            busy_ = false;
        } else if (!busy_) {
            busy_ = true;
            busy_since_ = clock_.now();
        } else if (clock_.now() - busy_since_ > options_.busy_timeout) {
            return abandon(request, foe_error::kNotDefined,
                           fmt::format("the slave stayed busy for {:.0f} ms ({} of {})",
                                       to_ms(clock_.now() - busy_since_), m->done, m->entire),
                           make_error_code(EcatErrc::MailboxTimeout));
        }
        return step(*m, request);
    }

protected:
    virtual Step step(const FoeMessage& m, std::vector<std::uint8_t>& request) = 0;

    /// Ends the transfer with `why` and tells the slave with an ERR (ETG.1000.6 §5.7: either
    /// side may end a transfer with an error request).
    Step abandon(std::vector<std::uint8_t>& request, std::uint32_t code, const std::string& why,
                 std::error_code ec = make_error_code(EcatErrc::ProtocolError)) {
        outcome.error = ec;
        outcome.sentence = fmt::format("{}: {}: {}", label, what, why);
        outcome.data.clear();
        encode_foe(request, FoeOpcode::Error, code, bytes_of(foe_error_text(code)));
        return Step::SendLast;
    }
    Step unexpected(const FoeMessage& m, std::vector<std::uint8_t>& request, const char* wanted) {
        return abandon(request, foe_error::kIllegal,
                       fmt::format("the slave sent FoE {} where {} was expected",
                                   opcode_name(m.opcode), wanted));
    }
    void report(std::size_t so_far, std::optional<std::size_t> total) const {
        if (options_.progress) {
            options_.progress(so_far, total);
        }
    }

    std::string name_;
    FoeOptions options_;
    std::size_t max_; ///< data bytes per DATA message in this direction
    IClock& clock_;
    bool busy_ = false;
    TimePoint busy_since_{};
};

class FoeRead final : public FoeTransfer {
public:
    using FoeTransfer::FoeTransfer;
    void first(std::vector<std::uint8_t>& request) override {
        encode_foe(request, FoeOpcode::ReadRequest, options_.password, bytes_of(name_));
    }

private:
    Step step(const FoeMessage& m, std::vector<std::uint8_t>& request) override {
        if (m.opcode == FoeOpcode::Busy) {
            return Step::Wait; // the slave prepares the file; its DATA follows on its own
        }
        if (m.opcode != FoeOpcode::Data) {
            return unexpected(m, request, "DATA");
        }
        if (m.value != packet_) {
            return abandon(request, foe_error::kPacketNumberWrong,
                           fmt::format("DATA packet {} where {} was expected", m.value, packet_));
        }
        if (outcome.data.size() + m.body.size() > options_.max_read_bytes) {
            return abandon(
                request, foe_error::kDiskFull,
                fmt::format("the file is larger than {} bytes", options_.max_read_bytes));
        }
        outcome.data.insert(outcome.data.end(), m.body.begin(), m.body.end());
        report(outcome.data.size(), std::nullopt);
        encode_foe(request, FoeOpcode::Ack, packet_);
        ++packet_;
        // A DATA shorter than the mailbox allows is the last one (ETG.1000.6 §5.7); its ACK
        // ends the transfer, nothing comes back for it.
        return m.body.size() < max_ ? Step::SendLast : Step::Send;
    }

    std::uint32_t packet_ = 1;
};

class FoeWrite final : public FoeTransfer {
public:
    FoeWrite(std::string name, std::vector<std::uint8_t> data, FoeOptions options,
             std::size_t mailbox, IClock& clock)
        : FoeTransfer(std::move(name), std::move(options), mailbox, clock), data_(std::move(data)) {
    }
    void first(std::vector<std::uint8_t>& request) override {
        encode_foe(request, FoeOpcode::WriteRequest, options_.password, bytes_of(name_));
    }

private:
    Step step(const FoeMessage& m, std::vector<std::uint8_t>& request) override {
        if (m.opcode == FoeOpcode::Busy) {
            // The slave could not take the last request yet: the same one goes again (with a
            // new mailbox counter, so it is not dropped as a repeat).
            report(sent_, data_.size());
            return Step::Send;
        }
        if (m.opcode != FoeOpcode::Ack) {
            return unexpected(m, request, "ACK");
        }
        if (m.value != packet_) {
            return abandon(request, foe_error::kPacketNumberWrong,
                           fmt::format("ACK of packet {} where {} was expected", m.value, packet_));
        }
        if (last_sent_) {
            return Step::Done;
        }
        if (max_ == 0) {
            return abandon(request, foe_error::kNotDefined, "the slave's mailbox is too small");
        }
        // The first ACK (0) answers the WRQ. A file that fills its last DATA exactly is ended by
        // an empty one.
        const std::size_t n = std::min(max_, data_.size() - sent_);
        ++packet_;
        encode_foe(request, FoeOpcode::Data, packet_,
                   std::span<const std::uint8_t>(data_).subspan(sent_, n));
        sent_ += n;
        last_sent_ = n < max_;
        report(sent_, data_.size());
        return Step::Send;
    }

    std::vector<std::uint8_t> data_;
    std::size_t sent_ = 0;
    std::uint32_t packet_ = 0; ///< the packet the next ACK must name
    bool last_sent_ = false;
};

} // namespace

std::unique_ptr<CoeTransfer> make_foe_read(std::string name, FoeOptions options,
                                           std::size_t mailbox_in, IClock& clock) {
    auto t = std::make_unique<FoeRead>(name, std::move(options), mailbox_in, clock);
    t->what = fmt::format("FoE read '{}'", name);
    return t;
}

std::unique_ptr<CoeTransfer> make_foe_write(std::string name, std::vector<std::uint8_t> data,
                                            FoeOptions options, std::size_t mailbox_out,
                                            IClock& clock) {
    const std::size_t size = data.size();
    auto t =
        std::make_unique<FoeWrite>(name, std::move(data), std::move(options), mailbox_out, clock);
    t->what = fmt::format("FoE write '{}' ({} bytes)", name, size);
    return t;
}

} // namespace codrive::ethercat::detail
