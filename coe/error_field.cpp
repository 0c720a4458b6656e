#include "coe/error_field.hpp"

namespace ecat::coe {
namespace {
constexpr std::uint8_t kCount = 0;
constexpr std::size_t kMaxDepth = 254;
constexpr unsigned kAdditionalShift = 16;
}  // namespace

ErrorField::ErrorField(ObjectStore& store) noexcept : store_(store) {
  if (store.slot(kIndex, kCount) == nullptr) return;
  std::size_t n = 0;
  while (n < kMaxDepth && store.slot(kIndex, static_cast<std::uint8_t>(n + 1)) != nullptr) ++n;
  depth_ = n;
  if (depth_ == 0) return;
  (void)store.set_hooks(kIndex, this);
  clear();
}

void ErrorField::clear() noexcept {
  for (std::size_t k = 1; k <= depth_; ++k) (void)store_.set<std::uint32_t>(kIndex, static_cast<std::uint8_t>(k), 0);
  (void)store_.set<std::uint8_t>(kIndex, kCount, 0);
}

void ErrorField::add(std::uint16_t error_code, std::uint16_t additional) noexcept {
  if (depth_ == 0 || error_code == 0) return;
  for (std::size_t k = depth_; k > 1; --k) {
    const auto older = store_.get<std::uint32_t>(kIndex, static_cast<std::uint8_t>(k - 1));
    (void)store_.set<std::uint32_t>(kIndex, static_cast<std::uint8_t>(k), older);
  }
  (void)store_.set<std::uint32_t>(kIndex, 1, error_code | (static_cast<std::uint32_t>(additional) << kAdditionalShift));
  const std::size_t count = store_.get<std::uint8_t>(kIndex, kCount);
  if (count < depth_) (void)store_.set<std::uint8_t>(kIndex, kCount, static_cast<std::uint8_t>(count + 1));
}

Expected<void, SdoAbort> ErrorField::on_write(ObjectStore&, const WriteRequest& request) noexcept {
  if (request.subindex != kCount) return {};  // the entries are the dictionary's (read-only)
  for (std::uint8_t b : request.data) {
    if (b != 0) return fail(SdoAbort::ValueRange);
  }
  return {};
}

void ErrorField::after_write(ObjectStore&, std::uint16_t, std::uint8_t subindex) noexcept {
  if (subindex == kCount) clear();
}

}  // namespace ecat::coe
