// SPDX-License-Identifier: Apache-2.0
// The ESI reader (ETG.2000) on the shipped devices/*.xml and on malformed files.
#include <codrive/ethercat/esi.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace codrive::ethercat {
namespace {

std::string device_file(const std::string& name) {
    return std::string(CODRIVE_SOURCE_DIR) + "/devices/" + name;
}

std::size_t occurrences(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) {
        ++n;
    }
    return n;
}

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Every device file: as many objects, PDOs and sync managers as the XML text holds.
TEST(EsiReader, ReadsEveryObjectPdoAndSyncManagerOfTheShippedFiles) {
    for (const char* name : {"akd2g.xml", "ds-bvs.xml", "fio.xml"}) {
        SCOPED_TRACE(name);
        const std::string path = device_file(name);
        const std::string text = read_text(path);
        const auto esi = load_esi(path);
        ASSERT_TRUE(esi) << esi.error();
        ASSERT_EQ(esi->devices.size(), 1U);
        const EsiDevice& d = esi->devices[0];
        EXPECT_EQ(d.objects.size(), occurrences(text, "<Object>"));
        EXPECT_EQ(d.rx_pdos.size(), occurrences(text, "<RxPdo "));
        EXPECT_EQ(d.tx_pdos.size(), occurrences(text, "<TxPdo "));
        EXPECT_EQ(d.sync_managers.size(), occurrences(text, "<Sm "));
        EXPECT_TRUE(d.coe);
        EXPECT_TRUE(d.pdo_assign);
    }
}

TEST(EsiReader, FioIdentityObjectsAndDefaultPdosAreTheManualsValues) {
    const auto esi = load_esi(device_file("fio.xml"));
    ASSERT_TRUE(esi) << esi.error();
    EXPECT_EQ(esi->vendor_id, 0x0048554BU);
    const EsiDevice& d = esi->devices.at(0);
    EXPECT_EQ(d.product_code, 0x0002BA67U);
    EXPECT_EQ(d.objects.size(), 130U);
    EXPECT_EQ(esi->match(0x0048554B, 0x0002BA67, 0), &d);
    // FIO manual ~7252: 607Ah default 4000 (little-endian DefaultData).
    const EsiEntry* target = d.entry(0x607A, 0);
    ASSERT_NE(target, nullptr);
    EXPECT_EQ(target->name, "Target position");
    EXPECT_EQ(target->type, DataType::Integer32);
    EXPECT_EQ(target->default_data, "A00F0000");
    EXPECT_EQ(target->access, Access::Rw);
    EXPECT_TRUE(target->rx_mappable);
    EXPECT_FALSE(target->tx_mappable);
    // FIO manual ~2858: 1003h holds 8 entries; the record's sub-items come from its DataType.
    const EsiObject* history = d.object(0x1003);
    ASSERT_NE(history, nullptr);
    ASSERT_EQ(history->entries.size(), 9U);
    EXPECT_EQ(history->entries[8].subindex, 8);
    EXPECT_EQ(history->entries[8].type, DataType::Unsigned32);
    EXPECT_EQ(history->entries[8].default_data, "00000000");
    // The default assignment: RxPDO 1600h on SM2, TxPDO 1A00h on SM3 (ETG.2000 Sm attribute).
    ASSERT_EQ(d.rx_pdos.size(), 4U);
    EXPECT_EQ(d.rx_pdos[0].index, 0x1600);
    EXPECT_EQ(d.rx_pdos[0].sm, 2);
    ASSERT_EQ(d.rx_pdos[0].entries.size(), 4U);
    EXPECT_EQ(d.rx_pdos[0].entries[0].index, 0x6040);
    EXPECT_EQ(d.rx_pdos[0].entries[0].bit_len, 16);
    EXPECT_FALSE(d.rx_pdos[1].sm.has_value());
    EXPECT_EQ(d.tx_pdos.at(0).sm, 3);
    ASSERT_EQ(d.sync_managers.size(), 4U);
    EXPECT_EQ(d.sync_managers[0].kind, "MBoxOut");
    EXPECT_EQ(d.sync_managers[0].start_address, 0x1000);
    EXPECT_EQ(d.sync_managers[0].default_size, 128);
    EXPECT_EQ(d.sync_managers[2].start_address, 0x1100);
}

TEST(EsiReader, MismatchNamesTheSlavesIdentityAndWhatTheFileDescribes) {
    const auto esi = load_esi(device_file("akd2g.xml"));
    ASSERT_TRUE(esi) << esi.error();
    EXPECT_EQ(esi->match(0x0048554B, 0x0002BA67, 0), nullptr);
    const std::string why = esi->mismatch(0x0048554B, 0x0002BA67, 0);
    EXPECT_NE(why.find("vendor 0x0048554B product 0x0002BA67 revision 0x00000000"),
              std::string::npos)
        << why;
    EXPECT_NE(why.find("akd2g.xml describes vendor 0x0000006A"), std::string::npos) << why;
    EXPECT_NE(why.find("product 0x11210100"), std::string::npos) << why;
    // Same vendor and product, another revision (newer firmware): the file still describes it.
    const EsiDevice* newer = esi->match(0x6A, 0x11210100, 0x03010000);
    ASSERT_NE(newer, nullptr);
    EXPECT_EQ(newer->product_code, 0x11210100U);
    // Another product of the same vendor: no match.
    EXPECT_EQ(esi->match(0x6A, 0x11210200, 0), nullptr);
}

std::string error_of(const std::string& text) {
    const auto esi = parse_esi(text, "bad.xml");
    return esi ? std::string("(read without error)") : esi.error();
}

TEST(EsiReader, MalformedFilesAreOneSentenceWithFileAndLine) {
    EXPECT_EQ(error_of("<EtherCATInfo>\n<Vendor>\n</EtherCATInfo>")
                  .rfind("bad.xml:3: not "
                         "well-formed XML",
                         0),
              0U)
        << error_of("<EtherCATInfo>\n<Vendor>\n</EtherCATInfo>");
    EXPECT_EQ(error_of("<?xml version=\"1.0\"?>\n<Foo/>"),
              "bad.xml:2: the root element is not <EtherCATInfo> (not an ESI file, ETG.2000 "
              "§5.1)");
    EXPECT_EQ(error_of("<EtherCATInfo>\n  <Vendor><Name>x</Name></Vendor>\n</EtherCATInfo>"),
              "bad.xml:2: <Vendor> needs <Id>, the vendor ID (ETG.2000 §5.2)");
    EXPECT_EQ(error_of("<EtherCATInfo><Vendor><Id>#xZZ</Id></Vendor></EtherCATInfo>"),
              "bad.xml:1: Vendor/Id is `#xZZ`, not a number 0..4294967295 (#xHEX or decimal, "
              "ETG.2000 HexDecValue)");
    EXPECT_EQ(error_of("<EtherCATInfo><Vendor><Id>2</Id></Vendor>\n<Descriptions/>"
                       "</EtherCATInfo>"),
              "bad.xml:1: the file describes no device (no Descriptions/Devices/Device)");
    const std::string head = "<EtherCATInfo><Vendor><Id>2</Id></Vendor><Descriptions><Devices>\n";
    const std::string tail = "</Devices></Descriptions></EtherCATInfo>";
    EXPECT_EQ(error_of(head + "<Device>\n<Type>x</Type></Device>" + tail),
              "bad.xml:3: a <Device> needs <Type ProductCode=\"#x...\"> (ETG.2000 §5.3.1: the "
              "product code the slave's SII must match)");
    EXPECT_EQ(error_of(head +
                       "<Device><Type ProductCode=\"1\">x</Type>\n<Profile><Dictionary>"
                       "<Objects>\n<Object><Name>n</Name><Type>UINT</Type></Object>"
                       "</Objects></Dictionary></Profile></Device>" +
                       tail),
              "bad.xml:4: an <Object> has no <Index>");
    EXPECT_EQ(error_of(head +
                       "<Device><Type ProductCode=\"1\">x</Type>\n<RxPdo>"
                       "<Index>#x1600</Index>\n<Entry><Index>#x6040</Index>"
                       "<BitLen>300</BitLen></Entry></RxPdo></Device>" +
                       tail),
              "bad.xml:4: an entry of PDO 1600h <BitLen> is `300`, not a number 0..255 (#xHEX "
              "or decimal, ETG.2000 HexDecValue)");
    EXPECT_EQ(error_of(head +
                       "<Device><Type ProductCode=\"1\">x</Type><Profile><Dictionary>"
                       "<Objects><Object><Index>#x6040</Index><Type>UINT</Type>\n<Flags>"
                       "<Access>rx</Access></Flags></Object></Objects></Dictionary>"
                       "</Profile></Device>" +
                       tail),
              "bad.xml:3: Flags/Access is `rx`; ETG.2000 allows ro, rw or wo");
    EXPECT_EQ(load_esi("/nonexistent/x.xml").error(),
              "/nonexistent/x.xml: cannot read the ESI file: No such file or directory");
}

} // namespace
} // namespace codrive::ethercat
