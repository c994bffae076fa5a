// CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320) for integrity checks: the
// controller artifact and the serial frames. It lives in the lowest module so that
// both `synthesis` and `io` can use it.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tmpc {

std::uint32_t crc32(const std::uint8_t* data, std::size_t n);

}  // namespace tmpc
