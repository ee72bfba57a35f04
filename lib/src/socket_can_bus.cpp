// SPDX-License-Identifier: Apache-2.0
// SocketCAN raw socket bus: batched non-blocking receive with kernel timestamps, error-frame
// decoding, and an allocation-free transmit retry ring for ENOBUFS/EAGAIN.
#include <codrive/core/socket_can_bus.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <optional>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

namespace codrive {
namespace {

constexpr std::size_t kBatch = 64;

std::int64_t to_ns(const timespec& t) {
    return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

// Kernel receive timestamps are CLOCK_REALTIME; protocol time is CLOCK_MONOTONIC. The offset
// between the two is sampled once per receive batch.
std::int64_t realtime_to_mono_offset() {
    timespec real_now{};
    timespec mono_now{};
    clock_gettime(CLOCK_REALTIME, &real_now);
    clock_gettime(CLOCK_MONOTONIC, &mono_now);
    return to_ns(mono_now) - to_ns(real_now);
}

Frame from_kernel(const canfd_frame& kf, std::size_t nbytes) {
    Frame f;
    const bool is_fd = nbytes == CANFD_MTU;
    if ((kf.can_id & CAN_ERR_FLAG) != 0) {
        f.flags |= Frame::kError;
        f.id = kf.can_id & CAN_ERR_MASK;
    } else if ((kf.can_id & CAN_EFF_FLAG) != 0) {
        f.flags |= Frame::kExtended;
        f.id = kf.can_id & CAN_EFF_MASK;
    } else {
        f.id = kf.can_id & CAN_SFF_MASK;
    }
    if ((kf.can_id & CAN_RTR_FLAG) != 0) {
        f.flags |= Frame::kRtr;
    }
    if (is_fd) {
        f.flags |= Frame::kFd;
        if ((kf.flags & CANFD_BRS) != 0) {
            f.flags |= Frame::kBrs;
        }
    }
    f.len = std::min<std::uint8_t>(kf.len, is_fd ? 64 : 8);
    std::memcpy(f.data.data(), kf.data, f.len);
    return f;
}

} // namespace

std::string describe_can_open_error(const std::string& ifname, const std::error_code& ec) {
    std::string hint;
    if (ec == CoreErrc::NoSocketCan) {
        // The socket() call failed with EAFNOSUPPORT: no CAN in this kernel at all (e.g. a
        // container host). A guest kernel with vcan is the way to run the tools here.
        hint = " (if the kernel has the modules: modprobe can-raw; otherwise run the tool inside "
               "a vcan guest with vcan-scripts/run-in-vcan.sh, see docs/vcan.md)";
    } else if (ec == CoreErrc::NoSuchInterface) {
        hint = " (check `ip link`; vcan-scripts/vcan-up.sh creates vcan0..vcan3, see "
               "docs/vcan.md)";
    } else if (ec == CoreErrc::InterfaceDown) {
        hint = " (bring it up: ip link set " + ifname + " up)";
    }
    return "cannot open " + ifname + ": " + ec.message() + hint;
}

bool socketcan_available() {
    const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (fd < 0) {
        return false;
    }
    ::close(fd);
    return true;
}

Result<std::unique_ptr<SocketCanBus>> SocketCanBus::open(const std::string& ifname,
                                                         SocketCanOptions options) {
    std::unique_ptr<SocketCanBus> bus(new SocketCanBus());
    bus->ifname_ = ifname;
    bus->opts_ = std::move(options);
    bus->tx_ring_.resize(std::max<std::size_t>(1, bus->opts_.tx_queue_capacity));
    bus->tx_batch_ = std::make_unique<TxBatch>();

    // A blocking socket: every send and receive passes MSG_DONTWAIT except the direct-read
    // fast path's receive, which blocks up to SO_RCVTIMEO.
    bus->fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (bus->fd_ < 0) {
        if (errno == EAFNOSUPPORT || errno == EPROTONOSUPPORT) {
            return fail(CoreErrc::NoSocketCan);
        }
        return fail_errno(errno);
    }
    const unsigned ifindex = if_nametoindex(ifname.c_str());
    if (ifindex == 0) {
        return fail(CoreErrc::NoSuchInterface);
    }
    const int fd = bus->fd_;
    const int loopback = bus->opts_.loopback ? 1 : 0;
    const int own = bus->opts_.receive_own ? 1 : 0;
    const can_err_mask_t err_mask = bus->opts_.error_frames ? CAN_ERR_MASK : 0;
    const int one = 1;
    setsockopt(fd, SOL_CAN_RAW, CAN_RAW_LOOPBACK, &loopback, sizeof(loopback));
    setsockopt(fd, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &own, sizeof(own));
    setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof(err_mask));
    if (bus->opts_.fd && setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &one, sizeof(one)) < 0) {
        return fail(CoreErrc::NotSupported);
    }
    if (bus->opts_.timestamps) {
        setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof(one));
    }
    setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof(one));
    if (bus->opts_.rcvbuf_bytes > 0) {
        const int size = bus->opts_.rcvbuf_bytes;
        if (setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &size, sizeof(size)) < 0) {
            setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &size, sizeof(size));
        }
    }
    if (bus->opts_.direct_read_limit > Duration::zero()) {
        const auto us =
            std::chrono::duration_cast<std::chrono::microseconds>(bus->opts_.direct_read_limit)
                .count();
        timeval tv{};
        tv.tv_sec = static_cast<time_t>(us / 1'000'000);
        tv.tv_usec = static_cast<suseconds_t>(us % 1'000'000);
        setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    }
    if (bus->opts_.sndbuf_bytes > 0) {
        const int size = bus->opts_.sndbuf_bytes;
        if (setsockopt(fd, SOL_SOCKET, SO_SNDBUFFORCE, &size, sizeof(size)) < 0) {
            setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &size, sizeof(size));
        }
    }
    if (auto r = bus->set_filters(bus->opts_.filters); !r) {
        return fail(r.error());
    }
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(ifindex);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) < 0) {
        if (errno == ENETDOWN) {
            return fail(CoreErrc::InterfaceDown);
        }
        if (errno == ENODEV) {
            return fail(CoreErrc::NoSuchInterface);
        }
        return fail_errno(errno);
    }
    return bus;
}

SocketCanBus::~SocketCanBus() {
    detach();
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

VoidResult SocketCanBus::set_filters(const std::vector<CanFilter>& filters) {
    if (filters.empty()) {
        can_filter all{};
        all.can_id = 0;
        all.can_mask = 0;
        if (setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, &all, sizeof(all)) < 0) {
            return fail_errno(errno);
        }
        return {};
    }
    std::vector<can_filter> kf;
    kf.reserve(filters.size());
    for (const auto& f : filters) {
        can_filter k{};
        if (f.extended) {
            k.can_id = (f.id & CAN_EFF_MASK) | CAN_EFF_FLAG;
            k.can_mask = (f.mask & CAN_EFF_MASK) | CAN_EFF_FLAG;
        } else {
            k.can_id = f.id & CAN_SFF_MASK;
            // Match only standard frames: include the EFF flag in the mask with value 0.
            k.can_mask = (f.mask & CAN_SFF_MASK) | CAN_EFF_FLAG;
        }
        if (f.invert) {
            k.can_id |= CAN_INV_FILTER;
        }
        kf.push_back(k);
    }
    if (setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, kf.data(),
                   static_cast<socklen_t>(kf.size() * sizeof(can_filter))) < 0) {
        return fail_errno(errno);
    }
    return {};
}

namespace {

/// `f` as the kernel takes it; returns the size to write (CAN_MTU or CANFD_MTU).
std::size_t to_kernel(const Frame& f, canfd_frame& kf) {
    kf = canfd_frame{};
    kf.can_id = f.id;
    if (f.extended()) {
        kf.can_id = (f.id & CAN_EFF_MASK) | CAN_EFF_FLAG;
    }
    if (f.rtr()) {
        kf.can_id |= CAN_RTR_FLAG;
    }
    if (f.error()) {
        kf.can_id = (f.id & CAN_ERR_MASK) | CAN_ERR_FLAG;
    }
    kf.len = f.len;
    std::size_t size = CAN_MTU;
    if (f.fd()) {
        size = CANFD_MTU;
        if ((f.flags & Frame::kBrs) != 0) {
            kf.flags |= CANFD_BRS;
        }
    }
    std::memcpy(kf.data, f.data.data(), f.len);
    return size;
}

} // namespace

struct SocketCanBus::TxBatch {
    std::array<canfd_frame, kTxBatch> frames{};
    std::array<iovec, kTxBatch> iov{};
    std::array<mmsghdr, kTxBatch> msgs{};
};

bool SocketCanBus::write_one(const Frame& f, int& err) {
    canfd_frame kf{};
    const std::size_t size = to_kernel(f, kf);
    const ssize_t n = ::send(fd_, &kf, size, MSG_DONTWAIT);
    if (n == static_cast<ssize_t>(size)) {
        ++stats_.tx_frames;
        return true;
    }
    err = n < 0 ? errno : EIO;
    return false;
}

std::size_t SocketCanBus::send_many(std::span<const Frame> frames) {
    std::size_t done = 0;
    if (tx_count_ > 0) {
        flush();
    }
    // Straight to the kernel while nothing waits in the ring (order) and it takes the frames.
    TxBatch& b = *tx_batch_;
    while (done < frames.size() && tx_count_ == 0) {
        const std::size_t want = std::min(kTxBatch, frames.size() - done);
        std::size_t k = 0;
        for (; k < want; ++k) {
            const Frame& f = frames[done + k];
            if (!f.valid() || (f.fd() && !opts_.fd)) {
                break; // send() below refuses it with its error
            }
            const std::size_t size = to_kernel(f, b.frames[k]);
            b.iov[k].iov_base = &b.frames[k];
            b.iov[k].iov_len = size;
            b.msgs[k].msg_hdr = msghdr{};
            b.msgs[k].msg_hdr.msg_iov = &b.iov[k];
            b.msgs[k].msg_hdr.msg_iovlen = 1;
        }
        if (k == 0) {
            break;
        }
        const int n = ::sendmmsg(fd_, b.msgs.data(), static_cast<unsigned>(k), MSG_DONTWAIT);
        if (n <= 0) {
            break; // full (ENOBUFS/EAGAIN) or failing: send() queues or reports, frame by frame
        }
        stats_.tx_frames += static_cast<std::uint64_t>(n);
        done += static_cast<std::size_t>(n);
        if (static_cast<std::size_t>(n) < k || k < want) {
            break;
        }
    }
    while (done < frames.size() && send(frames[done])) {
        ++done;
    }
    return done;
}

VoidResult SocketCanBus::send(const Frame& frame) {
    if (!frame.valid()) {
        return fail(CoreErrc::InvalidFrame);
    }
    if (frame.fd() && !opts_.fd) {
        return fail(CoreErrc::NotSupported);
    }
    // Keep order: while anything waits in the ring, new frames queue behind it.
    if (tx_count_ > 0) {
        flush();
    }
    if (tx_count_ == 0) {
        int err = 0;
        if (write_one(frame, err)) {
            return {};
        }
        if (err != ENOBUFS && err != EAGAIN) {
            if (err == ENETDOWN) {
                return fail(CoreErrc::InterfaceDown);
            }
            return fail_errno(err);
        }
    }
    if (tx_count_ == tx_ring_.size()) {
        ++stats_.tx_queue_full;
        return fail(CoreErrc::TxQueueFull);
    }
    tx_ring_[(tx_head_ + tx_count_) % tx_ring_.size()] = frame;
    ++tx_count_;
    ++stats_.tx_queued;
    retry_at_ = SteadyClock::now() + opts_.tx_retry;
    update_epollout();
    return {};
}

std::size_t SocketCanBus::flush() {
    while (tx_count_ > 0) {
        int err = 0;
        if (!write_one(tx_ring_[tx_head_], err)) {
            if (err == ENOBUFS || err == EAGAIN) {
                break;
            }
            // A frame the kernel refuses for good (e.g. interface down) is counted, reported and
            // dropped from the queue so one bad frame cannot wedge the bus.
            if (event_handler_) {
                BusEvent e;
                e.kind = BusEvent::Kind::ControllerProblem;
                e.detail = std::string("transmit failed: ") + std::strerror(err);
                event_handler_(e);
            }
        }
        tx_head_ = (tx_head_ + 1) % tx_ring_.size();
        --tx_count_;
    }
    if (tx_count_ == 0) {
        retry_at_ = kNever;
    } else {
        retry_at_ = SteadyClock::now() + opts_.tx_retry;
    }
    update_epollout();
    return tx_count_;
}

bool SocketCanBus::drain(Duration timeout) {
    const TimePoint end = SteadyClock::now() + timeout;
    while (flush() > 0) {
        if (SteadyClock::now() >= end) {
            return false;
        }
        pollfd p{fd_, POLLOUT, 0};
        ::poll(&p, 1, 1);
    }
    return true;
}

void SocketCanBus::update_epollout() {
    if (loop_ == nullptr) {
        return;
    }
    const bool want = tx_count_ > 0;
    if (want != want_out_) {
        want_out_ = want;
        (void)loop_->modify_fd(fd_, EPOLLIN | (want ? EPOLLOUT : 0U));
    }
}

VoidResult SocketCanBus::attach(EventLoop& loop) {
    detach();
    loop_ = &loop;
    want_out_ = false;
    auto r = loop.add_fd(fd_, EPOLLIN, [this](std::uint32_t events) {
        if ((events & EPOLLOUT) != 0U) {
            flush();
        }
        if ((events & (EPOLLIN | EPOLLERR)) != 0U) {
            const EventLoop::DirectRead got = read_batches(MSG_DONTWAIT);
            // The kernel timestamp is the time: the loop then needs no clock read of its own.
            if (got.newest && loop_ != nullptr) {
                loop_->note_time(*got.newest);
            }
        }
    });
    if (!r) {
        loop_ = nullptr;
        return r;
    }
    if (opts_.direct_read_limit > Duration::zero()) {
        (void)loop.set_direct_reader(
            fd_, [this] { return read_blocking(); }, opts_.direct_read_limit);
    }
    loop.add_timed(this);
    update_epollout();
    return {};
}

void SocketCanBus::detach() {
    if (loop_ != nullptr) {
        loop_->remove_fd(fd_);
        loop_->remove_timed(this);
        loop_ = nullptr;
    }
}

TimePoint SocketCanBus::to_monotonic(std::int64_t realtime_ns) {
    constexpr std::int64_t kResample = 1'000'000'000;
    if (rt_offset_sampled_at_ == 0 || realtime_ns - rt_offset_sampled_at_ > kResample ||
        realtime_ns < rt_offset_sampled_at_) {
        rt_offset_ns_ = realtime_to_mono_offset();
        rt_offset_sampled_at_ = realtime_ns;
    }
    return TimePoint(nanoseconds(realtime_ns + rt_offset_ns_));
}

TimePoint SocketCanBus::next_deadline() const {
    return tx_count_ > 0 ? retry_at_ : kNever;
}

void SocketCanBus::on_tick(TimePoint /*now*/) {
    flush();
}

std::size_t SocketCanBus::read_available() {
    return read_batches(MSG_DONTWAIT).count;
}

EventLoop::DirectRead SocketCanBus::read_blocking() {
    // MSG_WAITFORONE: block (up to SO_RCVTIMEO) for the first frame only, then take what waits.
    return read_batches(MSG_WAITFORONE);
}

EventLoop::DirectRead SocketCanBus::read_batches(int first_flags) {
    EventLoop::DirectRead out;
    int flags = first_flags;
    std::array<canfd_frame, kBatch> frames{};
    std::array<iovec, kBatch> iov{};
    std::array<mmsghdr, kBatch> msgs{};
    constexpr std::size_t kCtrlSize =
        CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t));
    alignas(cmsghdr) std::array<std::array<char, kCtrlSize>, kBatch> ctrl{};
    for (;;) {
        for (std::size_t i = 0; i < kBatch; ++i) {
            iov[i].iov_base = &frames[i];
            iov[i].iov_len = sizeof(canfd_frame);
            msgs[i].msg_hdr = msghdr{};
            msgs[i].msg_hdr.msg_iov = &iov[i];
            msgs[i].msg_hdr.msg_iovlen = 1;
            msgs[i].msg_hdr.msg_control = ctrl[i].data();
            msgs[i].msg_hdr.msg_controllen = kCtrlSize;
        }
        const int n = ::recvmmsg(fd_, msgs.data(), kBatch, flags, nullptr);
        flags = MSG_DONTWAIT;
        if (n <= 0) {
            break;
        }
        std::optional<TimePoint> now_cache;
        const auto now = [&now_cache] {
            if (!now_cache) {
                now_cache = SteadyClock::now();
            }
            return *now_cache;
        };
        for (int i = 0; i < n; ++i) {
            const auto idx = static_cast<std::size_t>(i);
            std::optional<TimePoint> rx_time;
            for (cmsghdr* c = CMSG_FIRSTHDR(&msgs[idx].msg_hdr); c != nullptr;
                 c = CMSG_NXTHDR(&msgs[idx].msg_hdr, c)) {
                if (c->cmsg_level != SOL_SOCKET) {
                    continue;
                }
                if (c->cmsg_type == SO_TIMESTAMPNS) {
                    timespec ts{};
                    std::memcpy(&ts, CMSG_DATA(c), sizeof(ts));
                    rx_time = to_monotonic(to_ns(ts));
                } else if (c->cmsg_type == SO_RXQ_OVFL) {
                    std::uint32_t drops = 0;
                    std::memcpy(&drops, CMSG_DATA(c), sizeof(drops));
                    if (drops != last_drop_count_) {
                        const std::uint32_t delta = drops - last_drop_count_;
                        last_drop_count_ = drops;
                        stats_.rx_dropped += delta;
                        if (event_handler_) {
                            BusEvent e;
                            e.kind = BusEvent::Kind::RxOverflow;
                            e.count = delta;
                            event_handler_(e);
                        }
                    }
                }
            }
            const std::size_t nbytes = msgs[idx].msg_len;
            if (nbytes != CAN_MTU && nbytes != CANFD_MTU) {
                continue;
            }
            const TimePoint t = rx_time ? *rx_time : now();
            if (rx_time) {
                out.newest = std::max(out.newest.value_or(t), t);
            }
            handle_frame(from_kernel(frames[idx], nbytes), t);
            ++out.count;
        }
        // A short batch means the socket is empty: no EAGAIN read to find that out.
        if (static_cast<std::size_t>(n) < kBatch) {
            break;
        }
    }
    return out;
}

void SocketCanBus::handle_frame(const Frame& f, TimePoint rx_time) {
    if (f.error()) {
        ++stats_.error_frames;
        if (event_handler_) {
            for (const auto& e : decode_error_frame(f)) {
                if (e.kind == BusEvent::Kind::StateChanged) {
                    state_ = e.state;
                }
                event_handler_(e);
            }
        }
        return;
    }
    ++stats_.rx_frames;
    if (frame_handler_) {
        frame_handler_(f, rx_time);
    }
}

namespace {

// Where in the frame a protocol error happened (CAN_ERR_PROT_LOC_*, the SJA1000's segment codes).
std::string_view error_location(std::uint8_t loc) {
    switch (loc) {
    case CAN_ERR_PROT_LOC_SOF:
        return "start of frame";
    case CAN_ERR_PROT_LOC_ID28_21:
        return "identifier bits 28-21 (11-bit: 10-3)";
    case CAN_ERR_PROT_LOC_ID20_18:
        return "identifier bits 20-18 (11-bit: 2-0)";
    case CAN_ERR_PROT_LOC_SRTR:
        return "SRR bit (11-bit: RTR bit)";
    case CAN_ERR_PROT_LOC_IDE:
        return "IDE bit";
    case CAN_ERR_PROT_LOC_ID17_13:
        return "identifier bits 17-13";
    case CAN_ERR_PROT_LOC_ID12_05:
        return "identifier bits 12-5";
    case CAN_ERR_PROT_LOC_ID04_00:
        return "identifier bits 4-0";
    case CAN_ERR_PROT_LOC_RTR:
        return "RTR bit";
    case CAN_ERR_PROT_LOC_RES1:
        return "reserved bit 1";
    case CAN_ERR_PROT_LOC_RES0:
        return "reserved bit 0";
    case CAN_ERR_PROT_LOC_DLC:
        return "data length code";
    case CAN_ERR_PROT_LOC_DATA:
        return "data field";
    case CAN_ERR_PROT_LOC_CRC_SEQ:
        return "CRC sequence";
    case CAN_ERR_PROT_LOC_CRC_DEL:
        return "CRC delimiter";
    case CAN_ERR_PROT_LOC_ACK:
        return "ACK slot";
    case CAN_ERR_PROT_LOC_ACK_DEL:
        return "ACK delimiter";
    case CAN_ERR_PROT_LOC_EOF:
        return "end of frame";
    case CAN_ERR_PROT_LOC_INTERM:
        return "intermission";
    default:
        return {};
    }
}

} // namespace

std::vector<BusEvent> decode_error_frame(const Frame& f) {
    std::vector<BusEvent> out;
    const std::uint32_t cls = f.id;
    const auto d = [&](std::size_t i) -> std::uint8_t { return i < f.len ? f.data[i] : 0; };
    const std::uint8_t tx = (cls & CAN_ERR_CNT) != 0 ? d(6) : 0;
    const std::uint8_t rx = (cls & CAN_ERR_CNT) != 0 ? d(7) : 0;
    auto push = [&](BusEvent::Kind kind, std::string detail = {},
                    BusState state = BusState::ErrorActive) {
        BusEvent e;
        e.kind = kind;
        e.state = state;
        e.detail = std::move(detail);
        e.tx_errors = tx;
        e.rx_errors = rx;
        out.push_back(std::move(e));
    };
    if ((cls & CAN_ERR_TX_TIMEOUT) != 0) {
        push(BusEvent::Kind::ControllerProblem, "transmit timeout");
    }
    if ((cls & CAN_ERR_LOSTARB) != 0) {
        push(BusEvent::Kind::LostArbitration, d(0) == CAN_ERR_LOSTARB_UNSPEC
                                                  ? std::string("bit unknown")
                                                  : "at bit " + std::to_string(d(0)));
    }
    if ((cls & CAN_ERR_CRTL) != 0) {
        const std::uint8_t c = d(1);
        if ((c & (CAN_ERR_CRTL_RX_OVERFLOW | CAN_ERR_CRTL_TX_OVERFLOW)) != 0) {
            push(BusEvent::Kind::ControllerProblem, (c & CAN_ERR_CRTL_RX_OVERFLOW) != 0
                                                        ? "controller receive buffer overflow"
                                                        : "controller transmit buffer overflow");
        }
        if ((c & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) != 0) {
            push(BusEvent::Kind::StateChanged, {}, BusState::ErrorPassive);
        } else if ((c & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) != 0) {
            push(BusEvent::Kind::StateChanged, {}, BusState::ErrorWarning);
        } else if ((c & CAN_ERR_CRTL_ACTIVE) != 0) {
            push(BusEvent::Kind::StateChanged, {}, BusState::ErrorActive);
        } else if (c == CAN_ERR_CRTL_UNSPEC) {
            push(BusEvent::Kind::ControllerProblem, "unspecified controller problem");
        }
    }
    if ((cls & CAN_ERR_PROT) != 0) {
        std::string what;
        const std::uint8_t t = d(2);
        if ((t & CAN_ERR_PROT_BIT) != 0) {
            what += "bit error ";
        }
        if ((t & CAN_ERR_PROT_FORM) != 0) {
            what += "form error ";
        }
        if ((t & CAN_ERR_PROT_STUFF) != 0) {
            what += "stuff error ";
        }
        if ((t & CAN_ERR_PROT_BIT0) != 0) {
            what += "dominant bit error ";
        }
        if ((t & CAN_ERR_PROT_BIT1) != 0) {
            what += "recessive bit error ";
        }
        if ((t & CAN_ERR_PROT_OVERLOAD) != 0) {
            what += "bus overload ";
        }
        if ((t & CAN_ERR_PROT_ACTIVE) != 0) {
            what += "active error announcement ";
        }
        if ((t & CAN_ERR_PROT_TX) != 0) {
            what += "on transmission ";
        }
        if (what.empty()) {
            what = "unspecified ";
        }
        what.pop_back();
        if (const auto where = error_location(d(3)); !where.empty()) {
            what += " in the ";
            what += where;
        } else if (d(3) != 0) {
            what += fmt::format(" (location 0x{:02X})", d(3));
        }
        push(BusEvent::Kind::ProtocolError, what);
    }
    if ((cls & CAN_ERR_TRX) != 0) {
        push(BusEvent::Kind::TransceiverError, fmt::format("status 0x{:02X}", d(4)));
    }
    if ((cls & CAN_ERR_ACK) != 0) {
        push(BusEvent::Kind::NoAck);
    }
    if ((cls & CAN_ERR_BUSOFF) != 0) {
        push(BusEvent::Kind::StateChanged, {}, BusState::BusOff);
    }
    if ((cls & CAN_ERR_BUSERROR) != 0 && (cls & CAN_ERR_PROT) == 0) {
        push(BusEvent::Kind::ProtocolError, "bus error");
    }
    if ((cls & CAN_ERR_RESTARTED) != 0) {
        push(BusEvent::Kind::Restarted);
    }
    if (out.empty()) {
        push(BusEvent::Kind::ControllerProblem,
             fmt::format("error frame with class 0x{:08X}", cls));
    }
    return out;
}

} // namespace codrive
