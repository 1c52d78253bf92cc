#include "auth.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <stdexcept>

namespace railcosim {
namespace {

constexpr std::uint32_t kK[64] = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

inline std::uint32_t rotr(std::uint32_t x, int n) {
  return (x >> n) | (x << (32 - n));
}

void compress(std::uint32_t h[8], const std::uint8_t block[64]) {
  std::uint32_t w[64];
  for (int i = 0; i < 16; ++i)
    w[i] = (std::uint32_t{block[4 * i]} << 24) | (std::uint32_t{block[4 * i + 1]} << 16) |
           (std::uint32_t{block[4 * i + 2]} << 8) | std::uint32_t{block[4 * i + 3]};
  for (int i = 16; i < 64; ++i) {
    const std::uint32_t s0 = rotr(w[i - 15], 7) ^ rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
    const std::uint32_t s1 = rotr(w[i - 2], 17) ^ rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
    w[i] = w[i - 16] + s0 + w[i - 7] + s1;
  }
  std::uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], k = h[7];
  for (int i = 0; i < 64; ++i) {
    const std::uint32_t t1 =
        k + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + kK[i] + w[i];
    const std::uint32_t t2 =
        (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
    k = g;
    g = f;
    f = e;
    e = d + t1;
    d = c;
    c = b;
    b = a;
    a = t1 + t2;
  }
  h[0] += a;
  h[1] += b;
  h[2] += c;
  h[3] += d;
  h[4] += e;
  h[5] += f;
  h[6] += g;
  h[7] += k;
}

}  // namespace

Digest sha256(std::string_view data) {
  std::uint32_t h[8] = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                        0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  std::string msg(data);
  const std::uint64_t bits = static_cast<std::uint64_t>(data.size()) * 8;
  msg += static_cast<char>(0x80);
  while (msg.size() % 64 != 56) msg += '\0';
  for (int i = 7; i >= 0; --i) msg += static_cast<char>((bits >> (8 * i)) & 0xff);
  for (std::size_t off = 0; off < msg.size(); off += 64)
    compress(h, reinterpret_cast<const std::uint8_t*>(msg.data() + off));
  Digest out;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 4; ++j) out[4 * i + j] = static_cast<std::uint8_t>(h[i] >> (24 - 8 * j));
  return out;
}

Digest hmac_sha256(std::string_view key, std::string_view message) {
  std::string k(key);
  if (k.size() > 64) {
    const Digest d = sha256(k);
    k.assign(d.begin(), d.end());
  }
  k.resize(64, '\0');
  std::string inner(64, '\0'), outer(64, '\0');
  for (int i = 0; i < 64; ++i) {
    inner[i] = static_cast<char>(k[i] ^ 0x36);
    outer[i] = static_cast<char>(k[i] ^ 0x5c);
  }
  const Digest ih = sha256(inner + std::string(message));
  return sha256(outer + std::string(ih.begin(), ih.end()));
}

std::string random_nonce() {
  std::random_device rd;  // the kernel's random source on Linux
  std::string n(32, '\0');
  for (std::size_t i = 0; i < n.size(); i += 4) {
    const std::uint32_t r = rd();
    for (std::size_t j = 0; j < 4; ++j) n[i + j] = static_cast<char>((r >> (8 * j)) & 0xff);
  }
  return n;
}

std::string auth_answer(std::string_view secret, std::string_view participant,
                        std::string_view nonce) {
  std::string msg = "railcosim-auth-v2";
  msg += participant;
  msg += '\0';
  msg += nonce;
  const Digest d = hmac_sha256(secret, msg);
  return std::string(d.begin(), d.end());
}

std::string auth_proof(std::string_view secret, std::string_view participant,
                       std::string_view hello_nonce, std::string_view challenge_nonce) {
  std::string msg = "railcosim-proof-v4";
  msg += participant;
  msg += '\0';
  msg += hello_nonce;
  msg += challenge_nonce;
  const Digest d = hmac_sha256(secret, msg);
  return std::string(d.begin(), d.end());
}

std::string proof_failure(std::string_view secret, std::string_view participant,
                          std::string_view hello_nonce, std::string_view challenge,
                          std::string_view proof) {
  if (challenge.empty())
    return "it asked no challenge, so it cannot prove that it holds the shared secret of "
           "--token-file (start it with the same --token-file, or find out what listens there)";
  if (!constant_time_equal(proof, auth_proof(secret, participant, hello_nonce, challenge)))
    return std::string(
               "it did not prove that it holds the shared secret of --token-file (its "
               "proof was ") +
           (proof.empty() ? "missing" : "wrong") + "): whatever listens there does not hold it";
  return "";
}

bool constant_time_equal(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

namespace {

// Opens without blocking (a FIFO's open waits for a writer otherwise) and
// takes only a regular file that its owner alone may read.
int open_token_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0)
    throw std::runtime_error("cannot read the token file " + path + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw std::runtime_error("the token file " + path +
                             " is not a regular file (a FIFO, device or folder); put the secret "
                             "in a plain file");
  }
  if ((st.st_mode & 077) != 0) {
    ::close(fd);
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw std::runtime_error("the token file " + path + " has mode " + mode +
                             ": others than its owner may read or change it; `chmod 600 " + path +
                             "`");
  }
  if (st.st_size > static_cast<off_t>(kMaxTokenFileBytes)) {
    ::close(fd);
    throw std::runtime_error("the token file " + path + " holds " + std::to_string(st.st_size) +
                             " bytes; a secret is at most " + std::to_string(kMaxTokenFileBytes));
  }
  return fd;
}

}  // namespace

std::string read_token_file(const std::string& path) {
  const int fd = open_token_file(path);
  // One byte more than allowed tells a file that grew since fstat.
  std::string t(kMaxTokenFileBytes + 1, '\0');
  std::size_t got = 0;
  while (got < t.size()) {
    const ssize_t n = ::read(fd, t.data() + got, t.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  if (got > kMaxTokenFileBytes)
    throw std::runtime_error("the token file " + path + " holds more than " +
                             std::to_string(kMaxTokenFileBytes) +
                             " bytes; a secret is not that long");
  t.resize(got);
  const auto first = t.find_first_not_of(" \t\r\n");
  const auto last = t.find_last_not_of(" \t\r\n");
  t = first == std::string::npos ? "" : t.substr(first, last - first + 1);
  if (t.size() < 16)
    throw std::runtime_error("the token file " + path +
                             " must hold a secret of at least 16 characters (e.g. `(umask 077; "
                             "head -c 32 /dev/urandom | base64 > " +
                             path + ")`)");
  return t;
}

bool is_loopback(const std::string& host) {
  return host == "::1" || host == "localhost" || host.rfind("127.", 0) == 0;
}

}  // namespace railcosim
