// A node's words are a peer's: its error message may hold escape sequences,
// a bell, a forged line ("\nmaster: all runs ok") or Markdown that breaks a
// table row and fetches an image. The two escapers (terminal, Markdown), and
// the master program and a study's REPORT.md against a node whose step
// failure says all of that: nothing arrives raw (it once did, byte for byte).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "fake_node.hpp"
#include "process_support.hpp"
#include "remote/peer_text.hpp"
#include "study/report.hpp"
#include "study/study.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;
using remote::markdown_text;
using remote::terminal_text;

// What a hostile node says when its step fails (valid UTF-8, as a protobuf
// string must be: the C1 control as U+009B).
const std::string kEvil =
    "boom \x1b[2J\x1b]0;owned\x07 bell\x07\r\nmaster: all runs ok\n| x | y |\n# Verdict\n"
    "![x](http://h/i.png) <img src=x> `code` \x7f \xc2\x9b"
    "2m \xe2\x80\xae";

TEST(PeerWords, TerminalTextEscapesEveryControlAndKeepsText) {
  EXPECT_EQ(terminal_text("a\x1b[31mb"), "a\\x1b[31mb");
  EXPECT_EQ(terminal_text("bell\x07"), "bell\\x07");
  EXPECT_EQ(terminal_text("a\nmaster: all runs ok"), "a\\nmaster: all runs ok");
  EXPECT_EQ(terminal_text("cr\rover"), "cr\\rover");
  EXPECT_EQ(terminal_text("tab\t."), "tab\\t.");
  EXPECT_EQ(terminal_text(std::string("nul\0.", 5)), "nul\\x00.");
  EXPECT_EQ(terminal_text("del\x7f"), "del\\x7f");
  // C1: a lone byte (8-bit CSI), and as UTF-8 (U+009B); a bidi override.
  EXPECT_EQ(terminal_text("\x9b"
                          "1m"),
            "\\x9b1m");
  EXPECT_EQ(terminal_text("\xc2\x9b"
                          "2m"),
            "\\u009b2m");
  EXPECT_EQ(terminal_text("\xe2\x80\xae"
                          "abc"),
            "\\u202eabc");
  // Invalid UTF-8: a lone continuation byte, a truncated sequence, overlong.
  EXPECT_EQ(terminal_text("\x80"), "\\x80");
  EXPECT_EQ(terminal_text("\xe2\x80"), "\\xe2\\x80");
  EXPECT_EQ(terminal_text("\xc0\xaf"), "\\xc0\\xaf");
  // Printable text and UTF-8 stay as they are.
  const std::string plain = "track node at 127.0.0.1:7002: |u| = 3 µm – 1e-9 (ok) \\x1b";
  EXPECT_EQ(terminal_text(plain), plain);
  // Idempotent, and never a control byte left.
  const std::string once = terminal_text(kEvil);
  EXPECT_EQ(terminal_text(once), once);
  for (const char c : once) {
    const auto b = static_cast<unsigned char>(c);
    EXPECT_TRUE(b >= 0x20 && b != 0x7f && !(b >= 0x80 && b <= 0x9f)) << once;
  }
}

TEST(PeerWords, MarkdownTextCannotBreakARowOrMakeALink) {
  EXPECT_EQ(markdown_text("a | b"), "a \\| b");
  EXPECT_EQ(markdown_text("![x](http://h/i.png)"), "\\!\\[x\\](http://h/i.png)");
  EXPECT_EQ(markdown_text("# Verdict"), "\\# Verdict");
  EXPECT_EQ(markdown_text("<img src=x>"), "&lt;img src=x&gt;");
  EXPECT_EQ(markdown_text("`code`"), "\\`code\\`");
  EXPECT_EQ(markdown_text("a\\|b"), "a\\\\\\|b");
  EXPECT_EQ(markdown_text("&#10;"), "&amp;\\#10;");
  EXPECT_EQ(markdown_text("row\n| forged |"), "row\\\\n\\| forged \\|");
  // What the runs write stays readable.
  EXPECT_EQ(markdown_text("not_converged (t = 0.001 s)"), "not_converged (t = 0.001 s)");
  const std::string md = markdown_text(kEvil);
  EXPECT_EQ(md.find('\n'), std::string::npos);
  EXPECT_EQ(md.find("!["), std::string::npos);
  EXPECT_EQ(md.find('<'), std::string::npos);
  for (std::size_t k = md.find('|'); k != std::string::npos; k = md.find('|', k + 1))
    EXPECT_EQ(md[k - 1], '\\') << md;
}

// A track node whose macro step 5 fails with kEvil (STEP_FAILED).
test::FakeNode::Edit fails_with_evil() {
  return [](const wire::Envelope& req, wire::Envelope& reply) {
    if (req.has_step() && req.step().step() == 5) {
      reply.Clear();
      reply.set_id(req.id());
      reply.mutable_error()->set_code(wire::Error::STEP_FAILED);
      reply.mutable_error()->set_message(kEvil);
      reply.mutable_error()->set_step(5);
    }
    return false;
  };
}

TEST(PeerWords, TheMasterPrintsANodesWordsEscaped) {
  test::FakeNode track("track", fails_with_evil());
  const fs::path dir = test::temp_dir("peer_words");
  const test::Outcome o = test::run_master(
      "run --scene " + test::source_path("scenes/paper.toml") +
      " --case wr-xx-jacobi --data-plane relay --node track=" + track.address().str() + " --out " +
      (dir / "out").string());
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_EQ(o.output.find('\x1b'), std::string::npos) << o.output;
  EXPECT_EQ(o.output.find('\x07'), std::string::npos) << o.output;
  EXPECT_EQ(o.output.find('\r'), std::string::npos) << o.output;
  EXPECT_EQ(o.output.find('\x7f'), std::string::npos) << o.output;
  EXPECT_EQ(o.output.find('\x9b'), std::string::npos) << o.output;
  // No line the node wrote starts a line of the master's output.
  std::istringstream lines(o.output);
  for (std::string line; std::getline(lines, line);) {
    EXPECT_NE(line.rfind("master: all runs ok", 0), 0u) << o.output;
    EXPECT_NE(line.rfind("| x | y |", 0), 0u) << o.output;
  }
  // The words are there, visibly escaped, with the node named.
  EXPECT_NE(o.output.find("track node at " + track.address().str() +
                          ": boom \\x1b[2J\\x1b]0;owned\\x07 bell\\x07\\r\\nmaster: all runs ok"),
            std::string::npos)
      << o.output;
  const std::string summary = test::read_file(dir / "out" / "wr-xx-jacobi" / "summary.json");
  EXPECT_NE(summary.find("\\\\x1b[2J"), std::string::npos) << summary;
  fs::remove_all(dir);
}

// REPORT.md of a study one of whose runs failed with kEvil (as collected
// from its summary.json, which a node's words reach).
TEST(PeerWords, ReportMdShowsANodesWordsAsText) {
  const fs::path dir = test::temp_dir("peer_words_report");
  fs::copy_file(test::source_path("scenes/paper.toml"), dir / "scene.toml");
  study::StudyReportInfo info;
  info.dir = dir;
  info.source_scene = "scenes/paper.toml";
  info.variants = {{"", ""}};
  info.figure_script = "/bin/false";
  study::StudyRun run;
  run.group = "case";
  run.folder = "wr-xx-jacobi_H1e-04";
  run.method = "wr-xx-jacobi";
  run.tolerance = 1e-7;
  run.record.case_name = "wr-xx-jacobi";
  run.record.status = "failed";
  run.record.message = kEvil;
  study::write_report(info, {run});
  const std::string md = test::read_file(dir / "REPORT.md");
  std::istringstream lines(md);
  int rows_with_run = 0;
  for (std::string line; std::getline(lines, line);) {
    EXPECT_NE(line.rfind("# Verdict", 0), 0u) << md;
    EXPECT_NE(line.rfind("master: all runs ok", 0), 0u) << md;
    if (line.find("wr-xx-jacobi_H1e-04") == std::string::npos) continue;
    ++rows_with_run;
    // One row: it starts and ends with a bar, and every bar of the node's
    // words is escaped, so the row has as many cells as its header.
    EXPECT_EQ(line.front(), '|') << line;
    EXPECT_EQ(line.back(), '|') << line;
    EXPECT_NE(line.find("boom \\\\x1b\\[2J"), std::string::npos) << line;
    EXPECT_NE(line.find("\\| x \\| y \\|"), std::string::npos) << line;
  }
  EXPECT_EQ(rows_with_run, 2) << md;  // the incomplete study's table, and every run's
  EXPECT_EQ(md.find("!["), std::string::npos) << md;
  EXPECT_EQ(md.find("<img"), std::string::npos) << md;
  EXPECT_EQ(md.find('\x1b'), std::string::npos) << md;
  EXPECT_EQ(md.find('\x07'), std::string::npos) << md;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace railcosim
