#pragma once
#include <cstdint>
#include <string>

namespace fscil {

// "4G", "4GiB", "512M", "1.5g" or "4294967296" -> bytes. K, M, G and T are powers of 1024, with
// an optional "iB" or "B"; a bare number is bytes. Throws CliError naming `option` on anything
// else, on zero and on sizes past 1 PiB.
std::int64_t parse_byte_size(const std::string& text, const std::string& option);

}  // namespace fscil
