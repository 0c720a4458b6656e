// The master code under test: a routine a master developer writes on their
// own master (here the ecatslave master library stands in for it) - bring
// every slave of a line to Op and report who is on it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "master/master.hpp"

namespace line {

struct Station {
  std::uint16_t address = 0;
  std::uint32_t vendor_id = 0;     // 1018h:01, read over CoE
  std::uint32_t product_code = 0;  // 1018h:02
};

// Scan, mailbox, PreOp, PDO sizes, process data, SafeOp (one exchange for
// valid outputs), Op. The first failure ends it with a message naming the
// slave and the step.
ecat::Expected<std::vector<Station>, std::string> start_line(ecat::master::Master& master);

}  // namespace line
