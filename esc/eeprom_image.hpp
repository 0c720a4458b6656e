// The SII EEPROM image an ESC loads and the master reads and writes through
// 0x0502-0x050F (ESC datasheet Section I §11; shared/spec/sii-eeprom.md).
// Shared copy-on-write (issue 16 item 5: a slave costs the memory it uses):
// slaves built from one description start with one image between them, and
// the first write through the EEPROM interface (mutable_data()) gives that
// ESC its own copy, so what one slave's EEPROM holds never
// changes another's. Reads see exactly the bytes a private copy would hold.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace ecat::esc {

class EepromImage {
 public:
  EepromImage() = default;
  // An image of its own (implicit: EscConfig::sii = bytes, as a vector was).
  EepromImage(std::vector<std::uint8_t> bytes)  // NOLINT(google-explicit-constructor)
      : bytes_(std::make_shared<std::vector<std::uint8_t>>(std::move(bytes))) {}
  // An image shared with every other holder of `shared` (and whoever else
  // keeps a pointer to it: the bytes are never written in place, even when
  // this is the last holder).
  explicit EepromImage(std::shared_ptr<std::vector<std::uint8_t>> shared)
      : bytes_(std::move(shared)), owned_(false) {}

  std::size_t size() const noexcept { return bytes_ ? bytes_->size() : 0; }
  bool empty() const noexcept { return size() == 0; }
  const std::uint8_t* data() const noexcept { return bytes_ ? bytes_->data() : nullptr; }
  std::uint8_t operator[](std::size_t i) const noexcept { return (*bytes_)[i]; }
  std::span<const std::uint8_t> bytes() const noexcept { return {data(), size()}; }

  // Writable bytes: the image is copied first when it is shared. Named, not
  // a non-const data()/operator[], so that reading a non-const image never
  // copies it by accident.
  std::uint8_t* mutable_data() { return own().data(); }

  // Whether a write would copy the bytes first (tests, memory checks).
  bool shared() const noexcept { return bytes_ && (!owned_ || bytes_.use_count() > 1); }

 private:
  std::vector<std::uint8_t>& own() {
    if (!bytes_) {
      bytes_ = std::make_shared<std::vector<std::uint8_t>>();
    } else if (!owned_ || bytes_.use_count() > 1) {
      bytes_ = std::make_shared<std::vector<std::uint8_t>>(*bytes_);
    }
    owned_ = true;
    return *bytes_;
  }

  std::shared_ptr<std::vector<std::uint8_t>> bytes_;
  bool owned_ = true;  // bytes_ came from this image's own vector (copies share it until written)
};

}  // namespace ecat::esc
