// Little-endian load/store over byte spans: every on-wire field in EtherCAT is
// little-endian (ETG.1000.4 §5.2), so every layer packs and unpacks through here.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

namespace ecat {

using Bytes = std::span<std::uint8_t>;
using ConstBytes = std::span<const std::uint8_t>;

// Reads an unsigned little-endian integer of sizeof(T) bytes at p.
// The caller guarantees p points at sizeof(T) readable bytes.
// On a little-endian host (not in constant evaluation) the load/store is
// one std::memcpy of the whole integer, which compilers turn into a single
// unaligned move; elsewhere the byte loop, with the same result.
template <typename T>
inline constexpr bool kNativeLe = std::endian::native == std::endian::little && !std::is_same_v<T, bool>;

template <typename T>
constexpr T load_le(const std::uint8_t* p) noexcept {
  static_assert(std::is_unsigned_v<T>);
  if constexpr (kNativeLe<T>) {
    if (!std::is_constant_evaluated()) {
      T v;
      std::memcpy(&v, p, sizeof(T));
      return v;
    }
  }
  T v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    v = static_cast<T>(v | (static_cast<T>(p[i]) << (8 * i)));
  }
  return v;
}

template <typename T>
constexpr void store_le(std::uint8_t* p, T v) noexcept {
  static_assert(std::is_unsigned_v<T>);
  if constexpr (kNativeLe<T>) {
    if (!std::is_constant_evaluated()) {
      std::memcpy(p, &v, sizeof(T));
      return;
    }
  }
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    p[i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
}

// Bounds-checked cursor over a read-only buffer. Once a read runs past the
// end the reader is marked failed and every later read returns 0, so a parser
// can read a whole header and check ok() once.
class ByteReader {
 public:
  constexpr explicit ByteReader(ConstBytes data) noexcept : data_(data) {}

  template <typename T>
  constexpr T read() noexcept {
    if (!ok_ || remaining() < sizeof(T)) {
      ok_ = false;
      return T{0};
    }
    T v = load_le<T>(data_.data() + pos_);
    pos_ += sizeof(T);
    return v;
  }
  constexpr std::uint8_t u8() noexcept { return read<std::uint8_t>(); }
  constexpr std::uint16_t u16() noexcept { return read<std::uint16_t>(); }
  constexpr std::uint32_t u32() noexcept { return read<std::uint32_t>(); }
  constexpr std::uint64_t u64() noexcept { return read<std::uint64_t>(); }

  // Takes the next n bytes as a sub-span (empty and failed if fewer remain).
  constexpr ConstBytes bytes(std::size_t n) noexcept {
    if (!ok_ || remaining() < n) {
      ok_ = false;
      return {};
    }
    ConstBytes out = data_.subspan(pos_, n);
    pos_ += n;
    return out;
  }
  constexpr ConstBytes rest() noexcept { return bytes(remaining()); }
  constexpr void skip(std::size_t n) noexcept { (void)bytes(n); }

  constexpr std::size_t remaining() const noexcept { return data_.size() - pos_; }
  constexpr std::size_t position() const noexcept { return pos_; }
  constexpr bool ok() const noexcept { return ok_; }

 private:
  ConstBytes data_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

// Bounds-checked cursor over a writable buffer; same failure rule as ByteReader.
class ByteWriter {
 public:
  constexpr explicit ByteWriter(Bytes data) noexcept : data_(data) {}

  template <typename T>
  constexpr void write(T v) noexcept {
    if (!ok_ || remaining() < sizeof(T)) {
      ok_ = false;
      return;
    }
    store_le<T>(data_.data() + pos_, v);
    pos_ += sizeof(T);
  }
  constexpr void u8(std::uint8_t v) noexcept { write(v); }
  constexpr void u16(std::uint16_t v) noexcept { write(v); }
  constexpr void u32(std::uint32_t v) noexcept { write(v); }
  constexpr void u64(std::uint64_t v) noexcept { write(v); }

  void bytes(ConstBytes src) noexcept {
    if (!ok_ || remaining() < src.size()) {
      ok_ = false;
      return;
    }
    if (!src.empty()) std::memcpy(data_.data() + pos_, src.data(), src.size());
    pos_ += src.size();
  }
  void fill(std::uint8_t value, std::size_t n) noexcept {
    if (!ok_ || remaining() < n) {
      ok_ = false;
      return;
    }
    std::memset(data_.data() + pos_, value, n);
    pos_ += n;
  }

  constexpr std::size_t remaining() const noexcept { return data_.size() - pos_; }
  constexpr std::size_t position() const noexcept { return pos_; }
  constexpr bool ok() const noexcept { return ok_; }
  constexpr Bytes written() const noexcept { return data_.first(pos_); }

 private:
  Bytes data_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace ecat
