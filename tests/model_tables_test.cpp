// The model's tables: the components, the cuts between them and the roles a
// node can serve. A new participant type is rows of these tables; these tests
// hold the rows to the rules the rest of the code relies on.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>

#include "cli/conform.hpp"
#include "cosim_case.hpp"
#include "model.hpp"
#include "process_support.hpp"
#include "scene.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace model_tables_test {

using cli::conform_case;

Scene scene_with_soil() {
  return load_scene(test::source_path("scenes/soil.toml"));
}

TEST(ComponentTable, RowsFollowTheEnumeratorsInLoadOrder) {
  ASSERT_EQ(static_cast<int>(components().size()), kComponentCount);
  std::set<std::string> names;
  for (int i = 0; i < kComponentCount; ++i) {
    const ComponentKind& k = components()[static_cast<std::size_t>(i)];
    EXPECT_EQ(static_cast<int>(k.id), i) << k.name;
    EXPECT_EQ(to_string(k.id), k.name);
    EXPECT_TRUE(names.insert(k.name).second) << "two components are called " << k.name;
    EXPECT_NE(k.present, nullptr) << k.name;
  }
  EXPECT_EQ(names, (std::set<std::string>{"vehicle", "rail", "sleepers", "soil"}));
}

TEST(ComponentTable, TheWholeModelHoldsWhatTheSceneModels) {
  const Parts fixed = Parts::all(test::paper_scene());
  const Parts soil = Parts::all(scene_with_soil());
  for (const ComponentKind& k : components()) {
    EXPECT_TRUE(soil.has(k.id)) << k.name;
    EXPECT_EQ(fixed.has(k.id), k.id != Component::kSoil) << k.name;
  }
}

TEST(CutTable, EachCutJoinsNeighboursAndIsListedInLoadOrder) {
  for (const CutKind& k : cut_kinds())
    EXPECT_EQ(static_cast<int>(k.lower), static_cast<int>(k.upper) + 1) << k.name;
  EXPECT_EQ(cut_names(), "wr, rs, ss");
  try {
    parse_case("rs-xx+wr-xx-jacobi");
    FAIL() << "cuts out of load order were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("in load order (wr, rs, ss)"), std::string::npos)
        << e.what();
  }
}

TEST(CutTable, ACutToAComponentTheSceneLacksSaysHowToAddIt) {
  try {
    partition(test::paper_scene(), parse_case("ss-xx-jacobi"));
    FAIL() << "a cut into a fixed soil was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("case ss-xx-jacobi: the sleepers/soil cut (ss) needs the soil"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("[soil] model = \"lumped\""), std::string::npos) << what;
  }
}

TEST(RoleTable, EveryHeldRangeHasARoleAndEveryRoleItsConformCase) {
  std::set<std::string> names;
  for (const RoleKind& r : roles()) {
    EXPECT_TRUE(names.insert(r.name).second) << "two roles are called " << r.name;
    EXPECT_EQ(find_role(r.name), &r);
    // The case `master conform` uses by default has a participant of this role.
    int found = 0;
    for (const ParticipantSpec& p : partition(scene_with_soil(), parse_case(r.conform_case)))
      found += p.role == r.name ? 1 : 0;
    EXPECT_EQ(found, 1) << r.name << " in " << r.conform_case;
  }
  EXPECT_EQ(role_names(), (std::vector<std::string>{"vehicle", "track", "rail", "soil"}));
  EXPECT_EQ(find_role("bridge"), nullptr);
  // Any contiguous run of components a participant can hold has a role.
  for (int first = 0; first < kComponentCount; ++first)
    for (int last = first; last < kComponentCount; ++last) {
      Parts p;
      for (int c = first; c <= last; ++c) p.add(static_cast<Component>(c));
      EXPECT_NE(find_role(role_of(p)), nullptr) << first << ".." << last;
    }
}

TEST(RoleTable, ANodeServesTheTablesRolesAndNoOther) {
  for (const std::string& role : role_names()) {
    const test::Outcome o = test::run_program("vehicle_node", "--role " + role + " --check");
    EXPECT_EQ(o.status, 0) << role << ": " << o.output;
    EXPECT_NE(o.output.find("would serve the " + role + " participant"), std::string::npos)
        << o.output;
  }
  const test::Outcome o = test::run_program("vehicle_node", "--role bridge --check");
  EXPECT_NE(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("bridge"), std::string::npos) << o.output;
  const test::Outcome help = test::run_program("vehicle_node", "--help");
  EXPECT_NE(help.output.find("vehicle, track, rail, soil, or any"), std::string::npos)
      << help.output;
}

TEST(RoleTable, ConformCasesComeFromTheTable) {
  EXPECT_EQ(conform_case("vehicle"), "wr-xx-jacobi");
  EXPECT_EQ(conform_case("rail"), "wr-xx+rs-xx-jacobi");
  EXPECT_EQ(conform_case("soil", "lumped"), "ss-xx-jacobi");
  EXPECT_EQ(conform_case("soil", "fe"), "ss-xt-jacobi");     // the FE soil takes forces only
  EXPECT_EQ(conform_case("soil", "green"), "ss-xt-jacobi");  // so does the Green's soil
  try {
    conform_case("bridge");
    FAIL() << "an unknown role was given a case";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'bridge'"), std::string::npos) << e.what();
  }
}

}  // namespace model_tables_test
}  // namespace railcosim
