// CRC-32 (IEEE 802.3, the polynomial zlib and PNG use), for .ptab checksums.
#pragma once

#include <cstddef>
#include <cstdint>

namespace patina {

// Continues a running CRC: crc32(crc32(0, a), b) == crc32(0, a + b).
uint32_t crc32(uint32_t crc, const void* data, size_t size);

}  // namespace patina
