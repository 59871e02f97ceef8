// Test helper: standard base64 (RFC 4648, padded), for glTF data URIs written by tests.
#pragma once

#include <cstdint>
#include <string>

namespace pelt::io {

inline std::string base64(const std::string& bytes) {
  static const char* b64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string enc;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t v = static_cast<uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<uint8_t>(bytes[i + 2]);
    enc += b64[(v >> 18) & 63];
    enc += b64[(v >> 12) & 63];
    enc += i + 1 < bytes.size() ? b64[(v >> 6) & 63] : '=';
    enc += i + 2 < bytes.size() ? b64[v & 63] : '=';
  }
  return enc;
}

}  // namespace pelt::io
