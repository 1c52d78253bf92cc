// The paper's findings are data (master/study/report_findings_table.cpp):
// each row states the paper's claim, the runs it compares and the tolerance
// its verdict is judged with. These tests pin every row against a committed
// fixture, so a claim, a tolerance or the runs a verdict reads cannot change
// without the change showing in review, and check that the tolerance a row
// states in words is the one its measure uses.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "study/report_findings.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace findings_table_test {

using study::amplified_and_biggest;
using study::error_ratio;
using study::fewer_unstable_runs;
using study::FindingMeasure;
using study::FindingRow;
using study::history_error_between;
using study::kFindingTable;
using study::lower_error_in_pairs;
using study::RunPair;
using study::stable_and_below_factor;

const char* measure_name(FindingMeasure m) {
  if (m == amplified_and_biggest) return "amplified_and_biggest";
  if (m == history_error_between) return "history_error_between";
  if (m == error_ratio) return "error_ratio";
  if (m == lower_error_in_pairs) return "lower_error_in_pairs";
  if (m == fewer_unstable_runs) return "fewer_unstable_runs";
  if (m == stable_and_below_factor) return "stable_and_below_factor";
  return "(a measure this test does not know)";
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Every field of every row, one per line.
std::string rendered_table() {
  std::ostringstream out;
  int n = 0;
  for (const FindingRow& r : kFindingTable) {
    out << "finding " << ++n << "\n";
    out << "  claim: " << r.claim << "\n  paper: " << r.paper << "\n  judged: " << r.judged
        << "\n  measure: " << measure_name(r.measure) << "\n  runs:";
    for (const std::string& run : r.runs) out << " " << run;
    out << "\n  pairs:";
    for (const RunPair& p : r.pairs)
      out << " [" << p.name << ": " << p.first << " | " << p.second << "]";
    out << "\n  sides:";
    for (const std::string& s : r.sides) out << " [" << s << "]";
    out << "\n  lower: " << r.lower << "\n  counted: [" << r.counted << "]"
        << "\n  paper_value: " << number(r.paper_value) << "\n  tolerance: " << number(r.tolerance)
        << "\n  note:" << (r.note.empty() ? "" : " " + r.note)
        << "\n  note_pair:" << (r.note_pair.empty() ? "" : " " + r.note_pair) << "\n";
  }
  return out.str();
}

TEST(FindingsTable, EveryRowIsAsCommitted) {
  const std::string fixture = test::source_path("tests/fixtures/findings_table.txt");
  const std::string now = rendered_table();
  if (const char* update = std::getenv("RAILCOSIM_UPDATE_FIXTURES"); update && *update == '1') {
    std::ofstream(fixture) << now;
    GTEST_SKIP() << "wrote " << fixture;
  }
  std::ifstream in(fixture);
  ASSERT_TRUE(in) << "missing " << fixture;
  std::stringstream committed;
  committed << in.rdbuf();
  EXPECT_EQ(committed.str(), now)
      << "the findings table differs from tests/fixtures/findings_table.txt: if the change to a "
         "claim, tolerance or run is meant, run this test with RAILCOSIM_UPDATE_FIXTURES=1 and "
         "commit the fixture with the reason";
}

// The rows with a number state it and its tolerance in words; the words must
// be the numbers the measure judges with.
TEST(FindingsTable, TheToleranceInWordsIsTheOneMeasured) {
  int numeric = 0;
  for (const FindingRow& r : kFindingTable) {
    if (r.measure == error_ratio) {
      ++numeric;
      const double lo = r.paper_value / r.tolerance, hi = r.paper_value * r.tolerance;
      std::ostringstream words;
      words << "within a factor " << r.tolerance << " of " << r.paper_value << " (" << lo << " to "
            << hi << ")";
      EXPECT_NE(r.judged.find(words.str()), std::string::npos)
          << r.claim << ": judged says \"" << r.judged << "\", expected \"" << words.str() << "\"";
    }
    if (r.measure == stable_and_below_factor) {
      ++numeric;
      ASSERT_EQ(r.tolerance, 2.0) << r.claim << ": the words below say twice";
      EXPECT_NE(r.judged.find("below twice"), std::string::npos) << r.judged;
    }
  }
  EXPECT_EQ(numeric, 2);
}

}  // namespace findings_table_test
}  // namespace railcosim
