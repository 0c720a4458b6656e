// The modular coupler's ESI (docs/esi-sii.md "Modular devices"): Slots and
// Modules as ETG.2000 lays them out, valid against the 1.14 and 1.17
// schemas; the device's own PDOs and objects only at device level; the
// device XML round trip keeps the modules; the SII carries the configured
// modules' PDOs at their slot indices.
#include <gtest/gtest.h>

#include <algorithm>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "esi/device_loader.hpp"
#include "esi/esi_reader.hpp"
#include "esi/esi_writer.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/sii_writer.hpp"
#include "esi/twin_judge.hpp"
#include "esi_xmllint.hpp"

namespace ecat::esi {
namespace {

const std::string kCoupler = std::string(ECAT_SOURCE_DIR) + "/xml/devices/mdp-coupler.xml";

od::DeviceDescription coupler() {
  auto d = load_device_file(kCoupler);
  EXPECT_TRUE(d.has_value()) << d.error().to_string();
  return d ? std::move(*d) : od::DeviceDescription{};
}

// One modular device in an ESI: `device` (its Sm, PDO, Mailbox and Slots
// elements) follows GroupType on line 11; `modules` is the Modules element's
// content.
std::string modular_esi(const std::string& product_code, const std::string& revision, const std::string& type,
                        const std::string& name, const std::string& device, const std::string& modules) {
  return R"(<?xml version="1.0"?>
<EtherCATInfo Version="1.2">
  <Vendor><Id>#xE0000001</Id><Name>V</Name></Vendor>
  <Descriptions>
    <Groups><Group><Type>G</Type><Name>G</Name></Group></Groups>
    <Devices>
      <Device Physics="YY">
        <Type ProductCode=")" + product_code + R"(" RevisionNo=")" + revision + R"(">)" + type + R"(</Type>
        <Name>)" + name + R"(</Name>
        <GroupType>G</GroupType>
)" + device + R"(
      </Device>
    </Devices>
    <Modules>
)" + modules + R"(
    </Modules>
  </Descriptions>
</EtherCATInfo>
)";
}

TEST(EsiModules, SlotsAndModulesAsEtg2000) {
  const std::string esi = write_esi(coupler());
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_string(esi.c_str()));
  auto desc = doc.child("EtherCATInfo").child("Descriptions");
  auto dev = desc.child("Devices").child("Device");
  // Device level: no module PDO, no module object; the MDP objects stay.
  EXPECT_FALSE(dev.child("RxPdo"));
  EXPECT_FALSE(dev.child("TxPdo"));
  std::vector<std::string> indices;
  for (auto o : dev.child("Profile").child("Dictionary").child("Objects").children("Object")) {
    indices.push_back(o.child_value("Index"));
  }
  for (const char* none : {"#x6000", "#x7010", "#x6020", "#x8020"}) {
    EXPECT_EQ(std::count(indices.begin(), indices.end(), none), 0) << none;
  }
  for (const char* mdp : {"#xF000", "#xF010", "#xF030", "#xF050"}) {
    EXPECT_EQ(std::count(indices.begin(), indices.end(), mdp), 1) << mdp;
  }
  auto slots = dev.child("Slots");
  ASSERT_TRUE(slots);
  EXPECT_STREQ(dev.child("Slots").next_sibling().name(), "Eeprom");
  EXPECT_STREQ(slots.attribute("SlotIndexIncrement").value(), "#x0010");
  EXPECT_STREQ(slots.attribute("SlotPdoIncrement").value(), "1");
  EXPECT_STREQ(slots.attribute("DownloadModuleIdentList").value(), "true");
  std::vector<pugi::xml_node> slot(slots.children("Slot").begin(), slots.children("Slot").end());
  ASSERT_EQ(slot.size(), 4u);
  EXPECT_STREQ(slot[1].attribute("MinInstances").value(), "1");
  EXPECT_STREQ(slot[3].attribute("MaxInstances").value(), "5");
  EXPECT_STREQ(slot[1].child_value("Name"), "Slot 2");
  auto def = slot[1].find_child_by_attribute("ModuleIdent", "Default", "1");
  EXPECT_STREQ(def.child_value(), "#x00010002");
  EXPECT_FALSE(slot[3].find_child_by_attribute("ModuleIdent", "Default", "1"));
  // Module types at slot-0 indices.
  std::vector<pugi::xml_node> mods(desc.child("Modules").children("Module").begin(),
                                   desc.child("Modules").children("Module").end());
  ASSERT_EQ(mods.size(), 3u);
  EXPECT_STREQ(mods[1].child("Type").attribute("ModuleIdent").value(), "#x00010002");
  EXPECT_STREQ(mods[1].child("Type").attribute("ModuleClass").value(), "DO");
  EXPECT_STREQ(mods[1].child_value("Type"), "MDP-DO8");
  auto rx = mods[1].child("RxPdo");
  EXPECT_STREQ(rx.child_value("Index"), "#x1600");
  EXPECT_STREQ(rx.child("Index").attribute("DependOnSlot").value(), "true");
  EXPECT_STREQ(rx.child("Entry").child_value("Index"), "#x7000");
  EXPECT_STREQ(rx.child("Entry").child("Index").attribute("DependOnSlot").value(), "true");
  auto ai_objects = mods[2].child("Profile").child("Dictionary").child("Objects");
  EXPECT_STREQ(ai_objects.child("Object").child_value("Index"), "#x6000");
  EXPECT_STREQ(ai_objects.child("Object").next_sibling("Object").child_value("Index"), "#x8000");
}

TEST(EsiModules, ValidAgainstBothSchemas) {
  if (!test::can_validate_esi()) GTEST_SKIP() << test::why_no_esi_schema();
  const std::string file = test::write_test_file("mdp-coupler-esi.xml", write_esi(coupler()));
  for (const auto& schema : test::esi_schemas()) {
    bool ok = false;
    const std::string out = test::xmllint_schema(file, schema, ok);
    EXPECT_TRUE(ok) << schema << ": " << out;
  }
}

TEST(EsiModules, DeviceXmlRoundTripKeepsTheModules) {
  const od::DeviceDescription d = coupler();
  const std::string xml = write_device_xml(d);
  EXPECT_NE(xml.find("<Plug module=\"#x00010003\""), std::string::npos);
  EXPECT_EQ(xml.find("index=\"#x7010\""), std::string::npos);  // the placed copy is not written
  auto again = load_device_string(xml, "roundtrip.xml");
  ASSERT_TRUE(again.has_value()) << again.error().to_string();
  EXPECT_EQ(write_esi(*again), write_esi(d));
  EXPECT_EQ(write_device_xml(*again), xml);
  ASSERT_NE(again->dictionary.find(0x7010), nullptr);
}

TEST(EsiModules, SiiCarriesTheConfiguredModulesPdos) {
  const SiiImage sii = sii_from_device(coupler());
  ASSERT_EQ(sii.rx_pdos.size(), 1u);
  EXPECT_EQ(sii.rx_pdos[0].index, 0x1601u);
  EXPECT_EQ(sii.rx_pdos[0].entries[7].index, 0x7010u);
  ASSERT_EQ(sii.tx_pdos.size(), 2u);
  EXPECT_EQ(sii.tx_pdos[0].index, 0x1A00u);
  EXPECT_EQ(sii.tx_pdos[1].index, 0x1A02u);
  EXPECT_EQ(sii.tx_pdos[1].entries[1].index, 0x6020u);
  EXPECT_EQ(sii.tx_pdos[1].entries[1].bit_length, 16u);
}

// ESI -> reader -> model: the slots' default modules are placed again, and
// the model writes the same ESI and (through the device XML) loads to it.
TEST(EsiModules, ReaderRoundTrip) {
  const od::DeviceDescription d = coupler();
  const std::string esi = write_esi(d);
  std::vector<EsiWarning> warnings;
  auto back = read_esi_string(esi, "coupler-esi.xml", {}, &warnings);
  ASSERT_TRUE(back.has_value()) << back.error().to_string();
  for (const auto& w : warnings) ADD_FAILURE() << w.element << ":" << w.line << ": " << w.message;
  ASSERT_TRUE(back->modular.has_value());
  EXPECT_EQ(back->modular->configured, d.modular->configured);
  EXPECT_EQ(back->modular->types.size(), 3u);
  EXPECT_EQ(back->modular->slots.size(), 4u);
  EXPECT_EQ(back->modular->slots[2].default_ident, std::optional<std::uint32_t>(0x00010003));
  ASSERT_NE(back->dictionary.find(0x7010), nullptr);
  EXPECT_EQ(back->dictionary.find(0x7010)->name, "DO Outputs");
  ASSERT_NE(back->dictionary.find(0x8020, 1), nullptr);
  EXPECT_EQ(back->dictionary.find(0x8020, 1)->max_value, (od::Value{7, 0}));
  ASSERT_EQ(back->rx_pdos.size(), 1u);
  EXPECT_EQ(back->rx_pdos[0].index, 0x1601u);
  EXPECT_EQ(back->rx_pdos[0].entries[0].index, 0x7010u);
  ASSERT_EQ(back->tx_pdos.size(), 2u);
  EXPECT_EQ(back->tx_pdos[1].entries[1].index, 0x6020u);
  EXPECT_EQ(write_esi(*back), esi);
  auto loaded = load_device_string(write_device_xml(*back), "coupler-device.xml");
  ASSERT_TRUE(loaded.has_value()) << loaded.error().to_string();
  EXPECT_EQ(write_esi(*loaded), esi);
}

// A vendor-shaped ESI: module PDO entries DependOnSlot on objects the module
// does not describe (as ETG's own Modules/Slots example has them) get
// process-data objects in the module and move with the slot.
TEST(EsiModules, DependOnSlotEntriesWithoutObjects) {
  const std::string esi = modular_esi("#x10000", "#x0", "Drive1", "Drive", R"(        <Sm MinSize="128" MaxSize="128" DefaultSize="128" StartAddress="#x1000" ControlByte="#x26" Enable="1">MBoxOut</Sm>
        <Sm MinSize="128" MaxSize="128" DefaultSize="128" StartAddress="#x1400" ControlByte="#x22" Enable="1">MBoxIn</Sm>
        <Sm StartAddress="#x1800" ControlByte="#x64" Enable="1">Outputs</Sm>
        <Sm StartAddress="#x1c00" ControlByte="#x20" Enable="1">Inputs</Sm>
        <Mailbox><CoE SdoInfo="true" PdoAssign="true" PdoConfig="true"/></Mailbox>
        <Slots SlotPdoIncrement="16" SlotIndexIncrement="#x800">
          <Slot MinInstances="1" MaxInstances="1"><Name>Axis 1</Name><ModuleIdent Default="1">#x100</ModuleIdent></Slot>
          <Slot MinInstances="1" MaxInstances="1"><Name>Axis 2</Name><ModuleIdent Default="1">#x100</ModuleIdent></Slot>
        </Slots>)", R"(      <Module>
        <Type ModuleIdent="#x0100">Position Mode</Type>
        <Name>CSP</Name>
        <RxPdo Fixed="true" Sm="2">
          <Index DependOnSlot="true">#x1600</Index><Name>Outputs</Name>
          <Entry><Index DependOnSlot="true">#x607A</Index><SubIndex>0</SubIndex><BitLen>32</BitLen><Name>Target</Name><DataType>DINT</DataType></Entry>
        </RxPdo>
        <TxPdo Fixed="true" Sm="3">
          <Index DependOnSlot="true">#x1a00</Index><Name>Inputs</Name>
          <Entry><Index DependOnSlot="true">#x6064</Index><SubIndex>0</SubIndex><BitLen>32</BitLen><Name>Position</Name><DataType>DINT</DataType></Entry>
        </TxPdo>
      </Module>)");
  std::vector<EsiWarning> warnings;
  auto d = read_esi_string(esi, "etg-shaped.xml", {}, &warnings);
  ASSERT_TRUE(d.has_value()) << d.error().to_string();
  ASSERT_TRUE(d->modular.has_value());
  EXPECT_EQ(d->modular->configured, (std::vector<std::uint32_t>{0x100, 0x100}));
  EXPECT_EQ(d->modular->index_increment, 0x800u);
  EXPECT_EQ(d->modular->pdo_increment, 16u);
  ASSERT_EQ(d->rx_pdos.size(), 2u);
  EXPECT_EQ(d->rx_pdos[1].index, 0x1610u);
  EXPECT_EQ(d->rx_pdos[1].entries[0].index, 0x687Au);
  EXPECT_EQ(d->tx_pdos[1].entries[0].index, 0x6864u);
  ASSERT_NE(d->dictionary.find(0x687A), nullptr);
  EXPECT_TRUE(d->dictionary.find(0x687A, 0)->access.rx_mappable());
  EXPECT_EQ(d->dictionary.find(0x6864, 0)->type, od::DataType::Integer32);
  // The loader derives the MDP objects the file lacks; from then on the chain
  // ESI -> model -> device XML -> model -> ESI is a fixed point.
  auto loaded = load_device_string(write_device_xml(*d), "etg-device.xml");
  ASSERT_TRUE(loaded.has_value()) << loaded.error().to_string();
  ASSERT_NE(loaded->dictionary.find(0xF050, 2), nullptr);
  EXPECT_EQ(loaded->dictionary.find(0xF050, 2)->default_value, (od::Value{0x00, 0x01, 0, 0}));
  const std::string esi2 = write_esi(*loaded);
  auto reread = read_esi_string(esi2, "etg-esi2.xml");
  ASSERT_TRUE(reread.has_value()) << reread.error().to_string();
  auto again = load_device_string(write_device_xml(*reread), "etg-device2.xml");
  ASSERT_TRUE(again.has_value()) << again.error().to_string();
  EXPECT_EQ(write_esi(*again), esi2);
}

// A modular device's own PDO numbered outside its range (fuzz_twin_judge's
// finding: a TxPdo 0000h beside two slots' TxPdos 1A00h/1A01h): the twin
// numbers it 1A02h and keeps the PDOs in index order, as the twin's own ESI
// reads back; the assignment 1C13h follows that order, so the chain
// ESI -> twin -> ESI is a fixed point (before, 1C13h was 1A02h 1A00h 1A01h
// on the first read and 1A00h 1A01h 1A02h on the second).
TEST(EsiModules, ARenumberedDevicePdoTakesItsPlaceInIndexOrder) {
  const std::string esi = modular_esi("#x2", "#x1", "Coupler", "Coupler", R"(        <Sm MinSize="34" MaxSize="128" DefaultSize="128" StartAddress="#x1000" ControlByte="#x26" Enable="1">MBoxOut</Sm>
        <Sm MinSize="34" MaxSize="128" DefaultSize="128" StartAddress="#x1080" ControlByte="#x22" Enable="1">MBoxIn</Sm>
        <Sm StartAddress="#x1100" ControlByte="#x64" Enable="1">Outputs</Sm>
        <Sm StartAddress="#x1180" ControlByte="#x20" Enable="1">Inputs</Sm>
        <TxPdo Fixed="1" Sm="3"><Index>0</Index><Name>Device status</Name>
          <Entry><Index>#xF100</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Status</Name><DataType>UINT</DataType></Entry>
        </TxPdo>
        <Mailbox><CoE SdoInfo="1" PdoAssign="1"/></Mailbox>
        <Slots SlotIndexIncrement="#x10" SlotPdoIncrement="1">
          <Slot MinInstances="1" MaxInstances="1"><Name>Port 1</Name><ModuleIdent Default="1">#x00020002</ModuleIdent></Slot>
          <Slot MinInstances="1" MaxInstances="1"><Name>Port 2</Name><ModuleIdent Default="1">#x00020002</ModuleIdent></Slot>
        </Slots>)", R"(      <Module>
        <Type ModuleIdent="#x00020002">Port</Type>
        <Name>Port</Name>
        <TxPdo Fixed="1" Sm="3">
          <Index DependOnSlot="true">#x1A00</Index><Name>Port inputs</Name>
          <Entry><Index DependOnSlot="true">#x6000</Index><SubIndex>0</SubIndex><BitLen>16</BitLen><Name>Input</Name><DataType>UINT</DataType></Entry>
        </TxPdo>
      </Module>)");
  std::vector<EsiWarning> warnings;
  auto d = read_esi_string(esi, "renumbered.xml", {}, &warnings);
  ASSERT_TRUE(d.has_value()) << d.error().to_string();
  const bool warned = std::any_of(warnings.begin(), warnings.end(), [](const EsiWarning& w) {
    return w.line == 15 && w.message == "TxPdo index 0000h is outside 1A00h..1BFFh; the twin numbers it 1A02h";
  });
  EXPECT_TRUE(warned);
  ASSERT_EQ(d->tx_pdos.size(), 3u);
  EXPECT_EQ(d->tx_pdos[0].index, 0x1A00u);
  EXPECT_EQ(d->tx_pdos[1].index, 0x1A01u);
  EXPECT_EQ(d->tx_pdos[2].index, 0x1A02u);
  EXPECT_EQ(d->tx_pdos[2].entries[0].index, 0xF100u);
  auto loaded = load_device_string(write_device_xml(*d), "renumbered-device.xml");
  ASSERT_TRUE(loaded.has_value()) << loaded.error().to_string();
  const od::Entry* second = loaded->dictionary.find(0x1C13, 2);
  ASSERT_NE(second, nullptr);
  EXPECT_EQ(second->default_value, (od::Value{0x01, 0x1A}));
  auto judged = judge_twin(*d);
  EXPECT_TRUE(judged.has_value()) << judged.error();
}

// Slots whose defaults configure more modules than F030h/F050h can list
// (fuzz_twin_judge's timeout: MinInstances 7000 placed 7000 modules, seconds
// of work, before the twin's loader refused the device) are refused at the
// Slots element, before any module is placed.
TEST(EsiModules, DefaultModulesBeyondTheIdentListAreRefused) {
  auto esi = [](const std::string& first_min) {
    return modular_esi("#x2", "#x1", "Coupler", "Coupler", R"(        <Slots>
          <Slot MinInstances=")" + first_min + R"(" MaxInstances="253"><Name>A</Name><ModuleIdent Default="1">#x1</ModuleIdent></Slot>
          <Slot MinInstances="1" MaxInstances="1"><Name>B</Name><ModuleIdent Default="1">#x1</ModuleIdent></Slot>
        </Slots>)", R"(      <Module>
        <Type ModuleIdent="#x1">M</Type>
        <Name>M</Name>
      </Module>)");
  };
  for (const char* min : {"7000", "254"}) {
    SCOPED_TRACE(min);
    auto d = read_esi_string(esi(min), "slots.xml");
    ASSERT_FALSE(d.has_value());
    EXPECT_EQ(d.error().to_string(),
              fmt::format("slots.xml:11: the slots' default modules number {} or more, more than the 254 that "
                          "F030h/F050h can list (the twin cannot represent this; the import refuses it)",
                          std::string(min) == "254" ? 255 : 7000));
  }
  auto fits = read_esi_string(esi("253"), "slots.xml");
  ASSERT_TRUE(fits.has_value()) << fits.error().to_string();
  ASSERT_TRUE(fits->modular.has_value());
  EXPECT_EQ(fits->modular->configured.size(), 254u);
}

}  // namespace
}  // namespace ecat::esi
