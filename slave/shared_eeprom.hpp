// One SII image in memory for every slave built from the same description
// (issue 16 item 5: memory per slave). esi::write_sii makes the same bytes
// for every slave of a description; the slaves share them copy-on-write
// (esc::EepromImage), so a thousand drives hold one image, and a slave the
// master writes through 0x0502 gets a copy of its own at its first write.
#pragma once

#include <cstdint>
#include <vector>

#include "esc/eeprom_image.hpp"

namespace ecat::slave {

// An image with the bytes `bytes`, shared with every other live image of
// equal bytes this function gave out (thread-safe; set-up only).
esc::EepromImage shared_eeprom_image(std::vector<std::uint8_t> bytes);

}  // namespace ecat::slave
