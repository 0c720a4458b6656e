// Which side of the ESC an access comes from: the EtherCAT side (datagrams)
// or the Process Data Interface (the local application). Many registers
// behave differently per side (ESC datasheet Section II, "ECAT"/"PDI" columns).
#pragma once

#include <cstdint>

namespace ecat::esc {

enum class Side : std::uint8_t { Ecat, Pdi };

}  // namespace ecat::esc
