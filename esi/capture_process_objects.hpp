// Objects a captured PDO maps but no dictionary describes (a slave without
// CoE has only its SII's PDO entries): created as process data the way the
// ESI import does (docs/twins.md "Import policy"): VAR for a lone subindex 0,
// else RECORD; rw + RxPDO-mappable or ro + TxPDO-mappable; default 0.
#pragma once

#include <string>
#include <vector>

#include "esi/sii_image.hpp"
#include "od/device.hpp"

namespace ecat::esi {

// A basic type of exactly `bits` bits (BOOLEAN, BITn, UNSIGNEDn), or none.
std::optional<od::DataType> type_of_bits(std::uint16_t bits) noexcept;

// Makes sure every non-gap entry of `pdo` exists in the dictionary; notes
// each object created. Entries whose object exists with another size are
// left to the loader's check, with a note.
void add_process_objects(const od::Pdo& pdo, od::DeviceDescription& device, std::vector<std::string>& notes);

// The SII's TXPDO/RXPDO categories as the default PDOs (capture_sii_pdos.cpp).
void apply_sii_pdos(const SiiImage& img, od::DeviceDescription& device, std::vector<std::string>& notes);

}  // namespace ecat::esi
