// Token files as a careless user or an attacker makes them: readable by
// others, endless (/dev/zero), huge, a FIFO nobody writes. The master and a
// node program each refuse at start-up, within a deadline, naming the file
// (and its mode); nothing is read into memory beyond a secret's bound.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "auth.hpp"
#include "process_support.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;
using test::Outcome;

fs::path secret_file(const fs::path& dir, const std::string& name, mode_t mode) {
  const fs::path p = dir / name;
  std::ofstream(p) << "a shared secret of the test run\n";
  ::chmod(p.c_str(), mode);
  return p;
}

// The node program and `master run --check` with the file: both must fail
// fast, with `expected` (and the file's name) in what they say.
void expect_refused(const std::string& path, const std::string& expected) {
  const auto start = std::chrono::steady_clock::now();
  const Outcome node = test::run_program(
      "vehicle_node", "--listen 127.0.0.1:0 --token-file " + path + " </dev/null");
  const Outcome master = test::run_master(
      "run --check --scene " + test::source_path("scenes/paper.toml") +
      " --case wr-xx-jacobi --transport tcp --out /tmp/unused --token-file " + path);
  for (const Outcome* o : {&node, &master}) {
    EXPECT_NE(o->status, 0) << o->output;
    EXPECT_NE(o->output.find("the token file " + path), std::string::npos) << o->output;
    EXPECT_NE(o->output.find(expected), std::string::npos) << o->output;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
}

TEST(TokenFile, OthersMayNotReadIt) {
  const fs::path dir = test::temp_dir("token_mode");
  expect_refused(secret_file(dir, "world", 0644).string(), "has mode 0644");
  expect_refused(secret_file(dir, "everyone", 0666).string(), "has mode 0666");
  expect_refused(secret_file(dir, "group", 0640).string(), "has mode 0640");
  EXPECT_EQ(read_token_file(secret_file(dir, "owner", 0600).string()),
            "a shared secret of the test run");
  EXPECT_EQ(read_token_file(secret_file(dir, "read_only", 0400).string()),
            "a shared secret of the test run");
  fs::remove_all(dir);
}

TEST(TokenFile, EndlessAndHugeFilesAreNotRead) {
  expect_refused("/dev/zero", "is not a regular file");
  const fs::path dir = test::temp_dir("token_huge");
  const fs::path huge = secret_file(dir, "huge", 0600);
  fs::resize_file(huge, 300u << 20);  // sparse: 300 MiB that take no disk
  expect_refused(huge.string(), "holds 314572800 bytes; a secret is at most 4096");
  fs::remove_all(dir);
}

TEST(TokenFile, AFifoIsRefusedWithoutWaitingForAWriter) {
  const fs::path dir = test::temp_dir("token_fifo");
  const fs::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_refused(fifo.string(), "is not a regular file");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace railcosim
