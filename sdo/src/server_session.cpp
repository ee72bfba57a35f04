// SPDX-License-Identifier: Apache-2.0
// The SDO server machine's data helpers: open an upload or download, move its data, send upload
// responses, segments and block sub-blocks (CiA 301 §7.2.4.3; CoE framing, ETG.1000.6 §5.6.2).
#include "server_session.hpp"

#include <codrive/sdo/complete_access.hpp>

namespace codrive::sdo::detail {

namespace {

tl::unexpected<SdoAbort> refuse(SdoAbort a) {
    return tl::unexpected(a);
}

} // namespace

/// The data of an upload: a domain reader or a copy of the dictionary value (so a value that
/// changes while segments go out stays consistent).
tl::expected<void, SdoAbort>
open_upload(Ctx& c, const std::map<std::uint32_t, DomainUploadHandler>& handlers) {
    auto& s = c.s;
    if (auto h = handlers.find(key(s.index, s.sub)); h != handlers.end()) {
        auto reader = h->second(s.index, s.sub);
        if (!reader) {
            return refuse(reader.error());
        }
        s.reader = std::move(*reader);
        return {};
    }
    if (s.complete_access) {
        auto whole = read_complete(c.od, s.index, s.sub);
        if (!whole) {
            return refuse(whole.error());
        }
        s.buffer = std::move(*whole);
    } else {
        auto bytes = c.od.read(s.index, s.sub);
        if (!bytes) {
            return refuse(bytes.error());
        }
        s.buffer.assign(bytes->begin(), bytes->end());
    }
    s.reader.size = s.buffer.size();
    s.reader.read = [&s, pos = std::size_t{0}](
                        std::span<std::uint8_t> out) mutable -> tl::expected<void, SdoAbort> {
        if (out.size() > s.buffer.size() - pos) {
            return refuse(SdoAbort::General);
        }
        std::copy_n(s.buffer.begin() + static_cast<std::ptrdiff_t>(pos), out.size(), out.begin());
        pos += out.size();
        return {};
    };
    return {};
}

/// Checks a download before accepting data (CiA 301: refuse early, with the precise code).
tl::expected<void, SdoAbort>
open_download(Ctx& c, const std::map<std::uint32_t, DomainDownloadHandler>& handlers,
              std::optional<std::size_t> size) {
    auto& s = c.s;
    s.buffer.clear();
    s.writer.reset();
    if (auto h = handlers.find(key(s.index, s.sub)); h != handlers.end()) {
        auto writer = h->second(s.index, s.sub, size);
        if (!writer) {
            return refuse(writer.error());
        }
        s.writer = std::move(*writer);
        return {};
    }
    if (s.complete_access) {
        return check_complete(c.od, s.index, s.sub); // entry sizes checked as they are written
    }
    const Object* obj = c.od.find(s.index);
    if (obj == nullptr) {
        return refuse(SdoAbort::NoObject);
    }
    const SubObject* sub = obj->find(s.sub);
    if (sub == nullptr) {
        return refuse(SdoAbort::NoSubindex);
    }
    if (!writable(sub->access)) {
        return refuse(SdoAbort::ReadOnly);
    }
    const std::size_t fixed = data_type_size(sub->type);
    if (size && fixed != 0) {
        if (*size > fixed) {
            return refuse(SdoAbort::LengthTooHigh);
        }
        if (*size < fixed) {
            return refuse(SdoAbort::LengthTooLow);
        }
    }
    return {};
}

bool write_data(Ctx& c, std::span<const std::uint8_t> data) {
    auto& s = c.s;
    if (s.writer) {
        if (data.empty()) {
            return true;
        }
        if (auto ok = s.writer->write(data); !ok) {
            s.write_error = ok.error();
            return false;
        }
        return true;
    }
    s.buffer.insert(s.buffer.end(), data.begin(), data.end());
    return true;
}

tl::expected<void, SdoAbort> commit_download(Ctx& c) {
    auto& s = c.s;
    if (s.writer) {
        auto w = std::move(*s.writer);
        s.writer.reset();
        return w.finish ? w.finish() : tl::expected<void, SdoAbort>{};
    }
    if (s.complete_access) {
        return write_complete(c.od, s.index, s.sub, s.buffer);
    }
    return c.od.write(s.index, s.sub, s.buffer);
}

void send_segment(Ctx& c) {
    auto& s = c.s;
    // CiA 301: 7 bytes a segment; CoE: as many as the mailbox holds, bytes past the 7th after the
    // frame with its seg data size 0 (ETG.1000.6 §5.6.2.6).
    const std::size_t n = std::min(c.framing.segment_room, s.reader.size - s.done);
    std::vector<std::uint8_t> data(n);
    if (n > 0) {
        if (auto ok = s.reader.read(data); !ok) {
            c.abort(ok.error());
            return;
        }
    }
    s.done += n;
    const bool last = s.done == s.reader.size;
    const std::span<const std::uint8_t> all(data);
    const std::size_t in_frame = std::min(n, kSegmentData);
    c.send(make_upload_segment(s.toggle, last, all.first(in_frame)), all.subspan(in_frame));
    s.toggle = !s.toggle;
    if (last) {
        c.complete();
    } else {
        c.arm();
    }
}

void send_sub_block(Ctx& c) {
    auto& s = c.s;
    SdoAbort err = SdoAbort::DataTransfer;
    const bool ok = s.sender.fill(s.block_size, [&](std::span<std::uint8_t> out) {
        auto r = s.reader.read(out);
        if (!r) {
            err = r.error();
        }
        return r.has_value();
    });
    if (!ok) {
        c.abort(err);
        return;
    }
    s.state = State::BlockUploadAck;
    for (std::uint8_t seq = 1; seq <= s.sender.segments(); ++seq) {
        c.send(s.sender.segment(seq));
    }
    c.arm();
}

/// Sends a sub-block response; `waiting`: a sub-block is expected next, so the response is
/// repeated if nothing of it arrives (only when the block size alternates, so that the client
/// can tell the copy from a new response — BlockSender::on_ack).
void send_flow(Ctx& c, const Payload& p, bool waiting) {
    auto& s = c.s;
    s.flow_frame = p;
    c.send(p);
    s.flow_sent =
        waiting && c.config.repeat_block_responses && c.config.block_size > 1 ? c.now : kNever;
    if (s.flow_sent != kNever) {
        s.deadline = std::min(s.deadline, c.now + c.config.block_gap_timeout);
    }
}

/// Initiate upload response for an opened upload; also used by a block upload that switches
/// protocol (size <= pst).
void respond_upload(Ctx& c) {
    auto& s = c.s;
    const std::size_t size = s.reader.size;
    if (size >= 1 && size <= kExpeditedMax && c.config.expedited_upload) {
        std::array<std::uint8_t, kExpeditedMax> data{};
        if (auto ok = s.reader.read(std::span<std::uint8_t>(data.data(), size)); !ok) {
            c.abort(ok.error());
            return;
        }
        c.send(make_initiate_upload_expedited(s.index, s.sub,
                                              std::span<const std::uint8_t>(data.data(), size)));
        c.complete();
        return;
    }
    if (size > 0xFFFFFFFFU) {
        c.abort(SdoAbort::LengthTooHigh);
        return;
    }
    s.toggle = false;
    s.done = 0;
    // CoE normal transfer (ETG.1000.6 §5.6.2.5): the response carries the first data after the
    // size; segments follow only for what does not fit. CAN's response carries none.
    std::vector<std::uint8_t> first(std::min(size, c.framing.initiate_room));
    if (!first.empty()) {
        if (auto ok = s.reader.read(first); !ok) {
            c.abort(ok.error());
            return;
        }
    }
    s.done = first.size();
    c.send(make_initiate_upload_segmented(s.index, s.sub, static_cast<std::uint32_t>(size)), first);
    if (c.framing.initiate_room > 0 && s.done == size) {
        c.complete();
        return;
    }
    s.state = State::UploadSegment;
    c.arm();
}

} // namespace codrive::sdo::detail
