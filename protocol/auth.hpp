// Who may drive a node, and which node a master may trust: a mutual
// challenge-response over a shared secret. The master's hello carries a fresh
// random nonce; the node sends its own; the master answers with
// HMAC-SHA256(secret, "railcosim-auth-v2" | participant | 0 | node nonce) and
// the node, once that is right, proves itself with auth_proof over both
// nonces. The secret never crosses the wire, and a recorded answer or proof
// is worthless for the next nonces.
#pragma once

#include <array>
#include <cstddef>
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
// The participant's proof that it holds the secret too, in its HelloReply
// after a right answer: HMAC-SHA256(secret, "railcosim-proof-v4" |
// participant | 0 | hello_nonce | challenge_nonce).
std::string auth_proof(std::string_view secret, std::string_view participant,
                       std::string_view hello_nonce, std::string_view challenge_nonce);
// Why a participant's answer to a hello that carried `hello_nonce` does not
// prove that it holds `secret` ("" when it does): `challenge` is the nonce it
// sent (empty: it asked none, so it has no secret), `proof` its
// HelloReply.proof.
std::string proof_failure(std::string_view secret, std::string_view participant,
                          std::string_view hello_nonce, std::string_view challenge,
                          std::string_view proof);
// Compares in time independent of where the inputs differ.
bool constant_time_equal(std::string_view a, std::string_view b);

// The longest token file read (a secret of 4 KiB is far more than enough).
inline constexpr std::size_t kMaxTokenFileBytes = 4096;

// Reads a shared secret from a file (surrounding white space dropped).
// Throws std::runtime_error naming the file if it cannot be read, is not a
// regular file (a FIFO is refused without waiting for a writer), may be read
// or written by others than its owner (mode & 077, as ssh refuses a key),
// holds more than kMaxTokenFileBytes or fewer than 16 characters.
std::string read_token_file(const std::string& path);

// True for 127.0.0.0/8 and ::1.
bool is_loopback(const std::string& host);

}  // namespace railcosim
