// Modular devices in the device format (docs/device-format.md "Modular
// devices"; ETG.5001.1, ETG.2000 Modules/Slots): the coupler's configured
// modules land at their slot indices (objects + n·10h, PDOs + n), the MDP
// objects F000h/F010h/F030h/F050h are derived with exact values, and every
// check names file:line.
#include <gtest/gtest.h>

#include <algorithm>

#include "esi/device_loader.hpp"

namespace ecat::esi {
namespace {

const std::string kCoupler = std::string(ECAT_SOURCE_DIR) + "/xml/devices/mdp-coupler.xml";
const std::string kName = std::string(ECAT_SOURCE_DIR) + "/tests/data/devices/inline.xml";

std::uint64_t u(const od::Value& v) {
  std::uint64_t n = 0;
  for (std::size_t k = v.size(); k-- > 0;) n = n << 8 | v[k];
  return n;
}

const od::Pdo* find_pdo(const od::DeviceDescription& d, std::uint16_t index) {
  const auto& list = index < 0x1A00 ? d.rx_pdos : d.tx_pdos;
  auto it = std::find_if(list.begin(), list.end(), [&](const od::Pdo& p) { return p.index == index; });
  return it == list.end() ? nullptr : &*it;
}

std::uint64_t def(const od::DeviceDescription& d, std::uint16_t index, std::uint8_t sub) {
  const od::Entry* e = d.dictionary.find(index, sub);
  EXPECT_NE(e, nullptr) << std::hex << index << ":" << int(sub);
  return e ? u(e->default_value) : ~0ull;
}

TEST(DeviceModules, CouplerObjectsAtTheirSlotIndices) {
  auto d = load_device_file(kCoupler);
  ASSERT_TRUE(d.has_value()) << d.error().to_string();
  // Slot 0 DI8 -> 6000h, slot 1 DO8 -> 7010h, slot 2 AI2 -> 6020h + 8020h.
  ASSERT_NE(d->dictionary.find(0x6000), nullptr);
  EXPECT_EQ(d->dictionary.find(0x6000)->name, "DI Inputs");
  EXPECT_EQ(d->dictionary.find(0x6000)->entries.size(), 9u);
  EXPECT_EQ(d->dictionary.find(0x6000, 8)->type, od::DataType::Boolean);
  EXPECT_EQ(d->dictionary.find(0x7010)->name, "DO Outputs");
  EXPECT_TRUE(d->dictionary.find(0x7010, 1)->access.rx_mappable());
  EXPECT_EQ(d->dictionary.find(0x6020)->name, "AI Inputs");
  EXPECT_EQ(d->dictionary.find(0x6020, 2)->type, od::DataType::Integer16);
  EXPECT_EQ(d->dictionary.find(0x8020)->name, "AI Settings");
  EXPECT_EQ(d->dictionary.find(0x8020, 1)->max_value, (od::Value{7, 0}));
  for (int none : {0x7000, 0x6010, 0x7020, 0x8000, 0x6030}) {
    EXPECT_EQ(d->dictionary.find(static_cast<std::uint16_t>(none)), nullptr) << std::hex << none;
  }
  // MDP objects (ETG.5001.1).
  EXPECT_EQ(def(*d, 0xF000, 0), 2u);
  EXPECT_EQ(def(*d, 0xF000, 1), 0x10u);  // module index distance
  EXPECT_EQ(def(*d, 0xF000, 2), 8u);     // 1 + 1 + 1 + 5 slots
  EXPECT_EQ(def(*d, 0xF010, 0), 3u);
  EXPECT_EQ(def(*d, 0xF050, 0), 3u);
  EXPECT_EQ(def(*d, 0xF050, 1), 0x00010001u);
  EXPECT_EQ(def(*d, 0xF050, 2), 0x00010002u);
  EXPECT_EQ(def(*d, 0xF050, 3), 0x00010003u);
  EXPECT_FALSE(d->dictionary.find(0xF050, 1)->access.writable_in(od::EsmState::PreOp));
  EXPECT_EQ(d->dictionary.find(0xF030)->entries.size(), 9u);
  EXPECT_EQ(def(*d, 0xF030, 0), 0u);  // not configured until the master writes it
  EXPECT_EQ(d->dictionary.find(0xF030, 0)->max_value, (od::Value{8}));
  EXPECT_TRUE(d->dictionary.find(0xF030, 0)->access.writable_in(od::EsmState::PreOp));
  EXPECT_FALSE(d->dictionary.find(0xF030, 3)->access.writable_in(od::EsmState::SafeOp));
  // PDOs at 1600h/1A00h + slot; entries moved with their module's objects.
  const od::Pdo* di = find_pdo(*d, 0x1A00);
  const od::Pdo* dout = find_pdo(*d, 0x1601);
  const od::Pdo* ai = find_pdo(*d, 0x1A02);
  ASSERT_TRUE(di && dout && ai);
  EXPECT_EQ(find_pdo(*d, 0x1600), nullptr);
  EXPECT_EQ(di->entries.size(), 8u);
  EXPECT_EQ(dout->entries[7].index, 0x7010u);
  EXPECT_EQ(dout->entries[7].subindex, 8u);
  EXPECT_EQ(ai->entries[1].index, 0x6020u);
  EXPECT_EQ(ai->bit_length(), 32u);
  EXPECT_EQ(ai->sm, std::optional<std::uint8_t>(3));
  // 1C12h/1C13h: the configured modules' PDOs.
  EXPECT_EQ(def(*d, 0x1C12, 0), 1u);
  EXPECT_EQ(def(*d, 0x1C12, 1), 0x1601u);
  EXPECT_EQ(def(*d, 0x1C13, 0), 2u);
  EXPECT_EQ(def(*d, 0x1C13, 1), 0x1A00u);
  EXPECT_EQ(def(*d, 0x1C13, 2), 0x1A02u);
  EXPECT_EQ(def(*d, 0x1A02, 1), 0x60200110u);
  // The model of the module types (slot-0 indices) for the ESI writer.
  ASSERT_TRUE(d->modular.has_value());
  const od::ModularDevice& m = *d->modular;
  EXPECT_EQ(m.index_increment, 0x10u);
  EXPECT_EQ(m.pdo_increment, 1u);
  ASSERT_EQ(m.types.size(), 3u);
  EXPECT_EQ(m.types[1].type, "MDP-DO8");
  EXPECT_EQ(m.types[1].objects[0].index, 0x7000u);
  ASSERT_EQ(m.types[1].rx_pdos.size(), 1u);
  EXPECT_EQ(m.types[1].rx_pdos[0].index, 0x1600u);
  EXPECT_EQ(m.types[1].rx_pdos[0].entries[0].index, 0x7000u);
  ASSERT_EQ(m.slots.size(), 4u);
  EXPECT_EQ(m.slots[3].min_instances, 0u);
  EXPECT_EQ(m.slots[3].max_instances, 5u);
  EXPECT_EQ(m.configured, (std::vector<std::uint32_t>{0x00010001, 0x00010002, 0x00010003}));
  EXPECT_EQ(m.max_modules(), 8u);
}

// A small modular device around the given <Modules> body.
std::string modular(std::string_view body) {
  return std::string(R"(<Device formatVersion="1">
  <Identity vendorId="0" name="M"/>
  <SyncManagers>
    <Sm index="0" type="MailboxOut" start="#x1000" size="128" control="#x26"/>
    <Sm index="1" type="MailboxIn" start="#x1080" size="128" control="#x22"/>
    <Sm index="2" type="Outputs" start="#x1100" maxSize="16" control="#x64"/>
    <Sm index="3" type="Inputs" start="#x1200" maxSize="16" control="#x20"/>
  </SyncManagers>
  <Objects>
    <Object index="#x6010" name="Taken" type="UNSIGNED8"/>
  </Objects>
  <Modules>
    <Module ident="#x11" type="IN">
      <Objects><Object index="#x6000" name="In" type="UNSIGNED8" pdo="tx"/></Objects>
      <TxPdo index="#x1A00" name="In" sm="3"><Entry index="#x6000" bits="8"/></TxPdo>
    </Module>
    <Module ident="#x22" type="OUT">
      <Objects><Object index="#x7000" name="Out" type="UNSIGNED16" access="rw" pdo="rx"/></Objects>
      <RxPdo index="#x1600" name="Out" sm="2"><Entry index="#x7000" bits="16"/></RxPdo>
    </Module>
)") + std::string(body) + "  </Modules>\n</Device>\n";
}

// The device's own 6010h moved out of slot 1's way.
void free_slot_one(std::string& xml) {
  const std::string taken = "<Object index=\"#x6010\" name=\"Taken\" type=\"UNSIGNED8\"/>";
  xml.replace(xml.find(taken), taken.size(), "<Object index=\"#x5000\" name=\"Spare\" type=\"UNSIGNED8\"/>");
}

LoadError error_of(const std::string& xml) {
  auto dev = load_device_string(xml, kName);
  EXPECT_FALSE(dev.has_value()) << "loaded although it should not";
  return dev ? LoadError{} : dev.error();
}

TEST(DeviceModules, PlugsOtherThanTheDefaults) {
  std::string xml = modular("    <Slot name=\"S\" min=\"1\" max=\"4\" modules=\"#x11 #x22\" default=\"#x11\"/>\n"
                            "    <Plug module=\"#x22\"/>\n    <Plug module=\"#x22\"/>\n");
  free_slot_one(xml);
  auto d = load_device_string(xml, kName);
  ASSERT_TRUE(d.has_value()) << d.error().to_string();
  EXPECT_NE(d->dictionary.find(0x7000), nullptr);
  EXPECT_NE(d->dictionary.find(0x7010), nullptr);
  EXPECT_NE(find_pdo(*d, 0x1600), nullptr);
  EXPECT_NE(find_pdo(*d, 0x1601), nullptr);
  EXPECT_EQ(find_pdo(*d, 0x1601)->entries[0].index, 0x7010u);
  EXPECT_EQ(def(*d, 0xF050, 0), 2u);
  EXPECT_EQ(def(*d, 0xF050, 2), 0x22u);
  EXPECT_EQ(def(*d, 0xF000, 2), 4u);
  EXPECT_EQ(def(*d, 0x1C12, 0), 2u);
}

TEST(DeviceModules, DefaultsWithoutPlugs) {
  std::string xml = modular("    <Slot name=\"A\" min=\"1\" max=\"1\" modules=\"#x22\" default=\"#x22\"/>\n"
                            "    <Slot name=\"B\" min=\"2\" max=\"2\" modules=\"#x11\" default=\"#x11\"/>\n");
  free_slot_one(xml);
  auto d = load_device_string(xml, kName);
  ASSERT_TRUE(d.has_value()) << d.error().to_string();
  EXPECT_EQ(d->modular->configured, (std::vector<std::uint32_t>{0x22, 0x11, 0x11}));
  EXPECT_NE(d->dictionary.find(0x7000), nullptr);  // slot 0
  EXPECT_NE(d->dictionary.find(0x6010), nullptr);  // slot 1
  EXPECT_NE(d->dictionary.find(0x6020), nullptr);  // slot 2
  EXPECT_NE(find_pdo(*d, 0x1A02), nullptr);
}

TEST(DeviceModules, Errors) {
  // Line 21 is the first Slot, line 22 the next element.
  auto e = error_of(modular("    <Slot name=\"S\" min=\"1\" max=\"2\" modules=\"#x11 #x33\"/>\n"));
  EXPECT_EQ(e.line, 21);
  EXPECT_EQ(e.message, "Slot 'S' names module #x00000033, which no Module declares");
  e = error_of(modular("    <Slot name=\"S\" min=\"1\" max=\"2\" modules=\"#x11\" default=\"#x22\"/>\n"));
  EXPECT_EQ(e.message, "Slot 'S': default module #x00000022 is not one of its modules");
  e = error_of(modular("    <Slot name=\"S\" min=\"3\" max=\"2\" modules=\"#x11\"/>\n"));
  EXPECT_EQ(e.message, "Slot 'S': min 3 and max 2 do not make 1 <= max and min <= max");
  e = error_of(modular("    <Slot name=\"S\" min=\"1\" max=\"2\" modules=\"#x11\"/>\n"));
  EXPECT_EQ(e.message, "Slot 'S' needs a default module: no Plug is given and it takes at least 1 module(s)");
  e = error_of(modular("    <Slot name=\"S\" min=\"1\" max=\"2\" modules=\"#x11\"/>\n    <Plug module=\"#x44\"/>\n"));
  EXPECT_EQ(e.line, 22);
  EXPECT_EQ(e.message, "Plug of module #x00000044, which no Module declares");
  e = error_of(modular("    <Slot name=\"S\" min=\"1\" max=\"1\" modules=\"#x11\"/>\n    <Plug module=\"#x22\"/>\n"));
  EXPECT_EQ(e.line, 22);
  EXPECT_EQ(e.message, "Slot 'S' needs at least 1 module(s) of #x11; 0 found (slot 0 holds module #x00000022)");
  e = error_of(modular("    <Slot name=\"S\" min=\"0\" max=\"1\" modules=\"#x11 #x22\"/>\n    <Plug module=\"#x22\"/>\n"
                       "    <Plug module=\"#x11\"/>\n"));
  EXPECT_EQ(e.line, 23);
  EXPECT_EQ(e.message, "module #x00000011 in slot 1 fits no Slot (the slots before it are full or do not accept it)");
  // Slot 1 of module 11h would put its 6000h at 6010h, which the device defines.
  e = error_of(modular("    <Slot name=\"S\" min=\"0\" max=\"2\" modules=\"#x11 #x22\"/>\n    <Plug module=\"#x22\"/>\n"
                       "    <Plug module=\"#x11\"/>\n"));
  EXPECT_EQ(e.line, 14);
  EXPECT_EQ(e.message, "slot 1 (module #x00000011): object 6000h would be 6010h, which is already defined (" + kName + ":10)");
  std::string dup = modular("    <Slot name=\"S\" min=\"0\" max=\"1\" modules=\"#x11\"/>\n    <Plug module=\"#x11\"/>\n");
  dup.replace(dup.find("ident=\"#x22\""), 12, "ident=\"#x11\"");
  e = error_of(dup);
  EXPECT_EQ(e.line, 17);
  EXPECT_EQ(e.message, "duplicate module ident #x00000011");
  e = error_of(modular("    <Slot name=\"S\" min=\"0\" max=\"2\" modules=\"#x11\"/>\n"));
  EXPECT_EQ(e.message, "a modular device needs at least one configured module");
  e = error_of(modular("    <Slot name=\"S\" min=\"0\" max=\"255\" modules=\"#x11\"/>\n"));
  EXPECT_EQ(e.message, "max '255' is out of range (0..254)");
}

}  // namespace
}  // namespace ecat::esi
