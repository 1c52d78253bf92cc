// Who may drive a node: a challenge-response over a shared secret. The node
// sends a fresh random nonce; the master answers with
// HMAC-SHA256(secret, "railcosim-auth-v2" | participant | 0 | nonce). The secret never
// crosses the wire, and a recorded answer is worthless for the next nonce.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace railcosim {

using Digest = std::array<std::uint8_t, 32>;

// SHA-256 (FIPS 180-4).
Digest sha256(std::string_view data);
// HMAC-SHA256 (RFC 2104).
Digest hmac_sha256(std::string_view key, std::string_view message);

// 32 bytes from the system's random source.
std::string random_nonce();

// The answer to a challenge, for the participant the hello named.
std::string auth_answer(std::string_view secret, std::string_view participant,
                        std::string_view nonce);
// Compares in time independent of where the inputs differ.
bool constant_time_equal(std::string_view a, std::string_view b);

// Reads a shared secret from a file (surrounding white space dropped).
// Throws std::runtime_error naming the file if it cannot be read or holds
// fewer than 16 characters.
std::string read_token_file(const std::string& path);

// True for 127.0.0.0/8 and ::1.
bool is_loopback(const std::string& host);

}  // namespace railcosim
