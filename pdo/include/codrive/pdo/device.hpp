// SPDX-License-Identifier: Apache-2.0
// Device-side PDO engine bound to an ObjectDictionary: the PDOs of a (simulated) node.
#pragma once

#include <codrive/core/can_bus.hpp>
#include <codrive/core/event_loop.hpp>
#include <codrive/core/object_dictionary.hpp>
#include <codrive/pdo/quirks.hpp>
#include <codrive/pdo/types.hpp>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace codrive::pdo {

struct DevicePdoOptions {
    NodeId node = 1;
    /// Enforced on SDO writes to the PDO objects (mapping only in pre-operational, RTR, ...).
    PdoQuirks quirks;
    /// SYNC COB-ID to react to in on_frame(); 0 = do not handle SYNC frames (the owner feeds
    /// on_sync() itself, e.g. from a sync::SyncConsumer hook).
    std::uint32_t sync_id = cob::kSync;
    /// Store received RPDO data with ObjectDictionary::write(force) so the OD's write hooks
    /// run (slower; the cyclic path stays allocation-free only if the hooks are).
    bool write_through_od = false;
};

enum class DevicePdoEventKind : std::uint8_t {
    RpdoTooShort,   ///< CiA 301: EMCY 8210h "PDO not processed due to length error"
    RpdoTooLong,    ///< EMCY 8220h "PDO length exceeded" (the frame is still processed)
    TpdoSendFailed, ///< the bus refused a TPDO
    RtrRefused,     ///< RTR for a TPDO whose COB-ID has bit 30 set
    MappingInvalid, ///< the OD holds a mapping that cannot be resolved (PDO kept off)
};

struct DevicePdoEvent {
    DevicePdoEventKind kind = DevicePdoEventKind::RpdoTooShort;
    PdoDir dir = PdoDir::Rpdo;
    std::uint8_t number = 0;
    std::uint32_t can_id = 0;
    std::uint8_t got_len = 0;
    std::uint8_t want_len = 0;
    TimePoint time{};
};
/// "node 5: RPDO1 (0x205) has 2 bytes but its mapping needs 6 (frame ignored, EMCY 8210h)".
[[nodiscard]] std::string to_string(const DevicePdoEvent& e, NodeId node);

/// Whether `e` may be mapped into a PDO of direction `dir` of a device with quirks `q`: the
/// object exists, is mappable in that direction and has that length (a BOOLEAN may be 1 bit,
/// CiA 301 §7.4.7.1); dummies 0001h..0007h only in RPDOs; index 0000h sub 00h with a length is
/// padding where `q.zero_index_padding` (AKD2G §3.11.1); whole bytes where `q.byte_aligned`.
/// SdoAbort{} if it may, SdoAbort::NotMappable (0x06040041) if not. Used by DevicePdo and by the
/// simulated EtherCAT slaves for their 16xxh/1Axxh mapping objects.
[[nodiscard]] SdoAbort check_mapping_entry(const ObjectDictionary& od, PdoDir dir,
                                           const PdoQuirks& q, MappingEntry e);

/// The PDO engine of one node.
///
/// It finds its PDOs in the OD (1400h–15FFh with 1600h–17FFh, 1800h–19FFh with 1A00h–1BFFh),
/// reads their configuration, and installs write hooks on those objects that enforce CiA 301
/// §7.5.2.35–38 and re-read the configuration after each accepted write:
///  - COB-ID change of a valid PDO, reserved or unsupported transmission types, inhibit time or
///    SYNC start value changed while the PDO is valid: 0x06090030;
///  - mapping written while the PDO is valid, entries written while sub 0 ≠ 0, or any mapping
///    write in operational when quirks.mapping_only_pre_operational: 0x08000022;
///  - an entry that does not exist, is not mappable in this direction or has the wrong length:
///    0x06040041; sub 0 making the PDO longer than 64 bits: 0x06040042; sub 0 above the number
///    of entries: 0x06090030.
/// A device with cob_id_read_only treats a PDO as valid when its mapping count is non-zero.
///
/// PDOs run only while operational (set_operational). RPDOs of types 0..240 are applied at the
/// next SYNC, 254/255 at once; each applied RPDO calls the RPDO hook. TPDOs go out on SYNC
/// (0: on the SYNC after a change, 1..240: every n-th SYNC from the SYNC start value), on RTR
/// (252: data sampled at SYNC, 253), or on change/event timer (254/255) with the inhibit time.
/// Mapped values are read from and written to the OD values in place: after start the cyclic
/// path does not allocate.
class DevicePdo final : public ITimed {
public:
    using RpdoHook = std::function<void(unsigned number, TimePoint now)>;
    using EventHandler = std::function<void(const DevicePdoEvent&)>;

    DevicePdo(ObjectDictionary& od, ICanBus& bus, DevicePdoOptions options);
    ~DevicePdo() override;
    DevicePdo(const DevicePdo&) = delete;
    DevicePdo& operator=(const DevicePdo&) = delete;

    /// Re-reads every PDO from the OD (call after changing the PDO objects with local writes
    /// that bypass the hooks, or after replacing objects the mapping points to).
    void reload();
    /// NMT state: PDOs are exchanged only while operational (CiA 301 Table 50).
    void set_operational(bool operational, TimePoint now = {});
    [[nodiscard]] bool operational() const { return operational_; }

    void set_rpdo_hook(RpdoHook hook) { rpdo_hook_ = std::move(hook); }
    void set_event_handler(EventHandler handler) { handler_ = std::move(handler); }

    /// SYNC frames (if options.sync_id), RPDOs and RTRs for TPDOs. True if used.
    bool on_frame(const Frame& frame, TimePoint now);
    /// A SYNC with its counter (0 if the SYNC carries none).
    void on_sync(std::uint8_t counter, TimePoint now);
    /// Application event for TPDO `number` (types 0, 254, 255): sent at the next SYNC (0) or
    /// now / after the inhibit time (254/255) even if the data did not change.
    void trigger(unsigned number, TimePoint now);
    /// Mapped data may have changed: event-driven TPDOs are compared at the next on_tick.
    void notify_changed() { check_changes_ = true; }

    [[nodiscard]] TimePoint next_deadline() const override;
    void on_tick(TimePoint now) override;

    /// Current configuration of a PDO as the engine uses it; nullptr if it does not exist.
    [[nodiscard]] const PdoConfig* config(PdoDir dir, unsigned number);
    /// True if the PDO exists, is valid and has a non-empty mapping.
    [[nodiscard]] bool active(PdoDir dir, unsigned number);
    [[nodiscard]] std::uint64_t sent(unsigned tpdo) const;
    [[nodiscard]] std::uint64_t received(unsigned rpdo) const;

private:
    struct Mapped {
        SubObject* sub = nullptr; ///< nullptr for dummies and padding
        std::uint16_t index = 0;
        std::uint8_t subindex = 0;
        std::uint8_t bit_offset = 0;
        std::uint8_t bits = 0;
    };
    struct Channel {
        PdoConfig config;
        bool active = false;
        std::uint8_t len = 0;
        std::vector<Mapped> entries;
        // runtime
        std::array<std::uint8_t, 8> last{}; ///< TPDO: last sent / RPDO: buffered for SYNC
        std::array<std::uint8_t, 8> sampled{};
        bool sampled_valid = false;
        bool rx_pending = false;
        bool sent_once = false;
        bool event_pending = false;
        bool started = false; ///< SYNC start value reached
        std::uint8_t sync_count = 0;
        TimePoint last_tx{};
        std::uint64_t count = 0;
    };

    void install_hooks();
    [[nodiscard]] tl::expected<void, SdoAbort> check_comm_write(Channel& ch, std::uint8_t sub,
                                                                std::span<const std::uint8_t> d);
    [[nodiscard]] tl::expected<void, SdoAbort> check_map_write(Channel& ch, std::uint8_t sub,
                                                               std::span<const std::uint8_t> d);
    [[nodiscard]] SdoAbort check_entry(const Channel& ch, MappingEntry e) const;
    [[nodiscard]] bool pdo_valid(const Channel& ch) const;
    void load(Channel& ch);
    void refresh() {
        if (dirty_) {
            reload();
        }
    }
    Channel* find(PdoDir dir, unsigned number);
    void compose(const Channel& ch, std::array<std::uint8_t, 8>& out) const;
    void apply(Channel& ch, const std::uint8_t* data, TimePoint now);
    void transmit(Channel& ch, const std::array<std::uint8_t, 8>& data, TimePoint now);
    void emit(DevicePdoEventKind kind, const Channel& ch, TimePoint now, std::uint8_t got = 0);
    void run_events(TimePoint now);

    ObjectDictionary& od_;
    ICanBus& bus_;
    DevicePdoOptions options_;
    std::vector<Channel> channels_; ///< RPDOs then TPDOs
    bool operational_ = false;
    bool dirty_ = false;
    bool check_changes_ = false;
    TimePoint next_ = kNever;
    RpdoHook rpdo_hook_;
    EventHandler handler_;
};

} // namespace codrive::pdo
