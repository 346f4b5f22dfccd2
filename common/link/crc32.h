// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320) for frames and scan-file records.
#pragma once
#include <cstddef>
#include <cstdint>

namespace dg {

// Continue a CRC over more bytes: crc32_update(crc32_update(0, a), b) == crc32(a + b).
uint32_t crc32_update(uint32_t crc, const uint8_t* data, size_t size);

inline uint32_t crc32(const uint8_t* data, size_t size) { return crc32_update(0, data, size); }

}  // namespace dg
