// Fallible calls return values (STYLE lesson 6): tl::expected from Debian's
// libexpected-dev until std::expected is available on every compiler we use.
#pragma once

#include <tl/expected.hpp>

namespace ecat {

template <typename T, typename E>
using Expected = tl::expected<T, E>;

template <typename E>
constexpr tl::unexpected<E> fail(E e) {
  return tl::unexpected<E>(e);
}

}  // namespace ecat
