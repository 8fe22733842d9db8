#pragma once
#include <cstdint>
#include <string>

namespace fscil {

// "4G", "4Gi", "4GiB", "4GB", "512M", "1.5g", "4096B" or "4294967296" -> bytes. K, M, G and T
// are powers of 1024 (so 4GB is 4 GiB, as free and top count); a number without one is whole
// bytes. Throws CliError naming `option` on anything else, on zero and past 1024T.
std::int64_t parse_byte_size(const std::string& text, const std::string& option);

}  // namespace fscil
