// The devices of an ENI's chain (ETG.2100 Config/Slave, in the ENI's order):
// each slave gets the identity, mailbox and process-data layout of the ENI;
// its dictionary comes from the matching ESI in an ESI directory (same vendor
// id, product code and revision) or, where there is none, is synthesised from
// the ENI: the PDOs with their entries, the objects they map, and every object
// the CoE InitCmds write, so that the master's InitCmds are accepted as the
// device would accept them. Decisions: docs/twins.md "Networks from an ENI".
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "esi/device_error.hpp"
#include "esi/eni_reader.hpp"
#include "esi/esi_reader.hpp"
#include "od/device.hpp"

namespace ecat::esi {

struct EniDevice {
  od::DeviceDescription device;
  std::string esi_file;  // the ESI the dictionary came from; "" if synthesised
};

// `esi_dir` empty: every dictionary is synthesised. Warnings name the ENI
// (or ESI) line of what was repaired or left out.
Expected<std::vector<EniDevice>, LoadError> eni_devices(const EniNetwork& network,
                                                        const std::filesystem::path& esi_dir,
                                                        std::vector<EsiWarning>* warnings = nullptr);

// The device file (docs/device-format.md) that stands for a slave without an
// ESI, and for each of its lines the ENI line it comes from (index 0 = line 1).
// `error` (with eni_lines = {line}) if the ENI cannot be made into a device.
struct EniDeviceXml {
  std::string xml;
  std::vector<SourcePos> eni_lines;
  std::string error;
};
EniDeviceXml eni_device_xml(const EniSlave& slave, std::vector<EsiWarning>* warnings = nullptr);

}  // namespace ecat::esi
