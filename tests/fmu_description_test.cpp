// An FMU's modelDescription.xml (fmu/description): the test FMUs' own, and
// descriptions that are refused: model exchange only, another FMI version,
// values that are not numbers, counts over the bounds, and descriptions
// that lie about their variables.
#include <gtest/gtest.h>

#include <string>

#include "description.hpp"
#include "fmu_error.hpp"

namespace fmu_description_test {
using namespace railcosim::fmu;

const std::string kFmus = std::string(RAILCOSIM_SOURCE_DIR) + "/tests/fmus/";

// The message of the refusal of `xml`.
std::string refusal(const std::string& xml, const DescriptionLimits& limits = {}) {
  try {
    parse_model_description(xml, "test.xml", limits);
  } catch (const FmuError& e) {
    return e.what();
  }
  ADD_FAILURE() << "not refused:\n" << xml;
  return "";
}

// An FMI 2.0 description with `variables` inside <ModelVariables> and
// `structure` inside <ModelStructure>.
std::string fmi2(const std::string& variables, const std::string& structure = "") {
  return R"(<fmiModelDescription fmiVersion="2.0" modelName="m" guid="g">
    <CoSimulation modelIdentifier="m"/><ModelVariables>)" +
         variables + "</ModelVariables><ModelStructure>" + structure +
         "</ModelStructure></fmiModelDescription>";
}
std::string fmi3(const std::string& variables, const std::string& structure = "") {
  return R"(<fmiModelDescription fmiVersion="3.0" modelName="m" instantiationToken="t">
    <CoSimulation modelIdentifier="m"/><ModelVariables>)" +
         variables + "</ModelVariables><ModelStructure>" + structure +
         "</ModelStructure></fmiModelDescription>";
}
const std::string kReal2 =
    R"(<ScalarVariable name="x" valueReference="0" causality="output"><Real/></ScalarVariable>)";

TEST(FmuDescription, ReadsTheFmi2TestFmu) {
  const ModelDescription d = read_model_description(kFmus + "dahlquist2.xml");
  EXPECT_EQ(d.version, FmiVersion::k2);
  EXPECT_EQ(d.model_identifier, "dahlquist2");
  EXPECT_EQ(d.token, "{railcosim-dahlquist2}");
  EXPECT_TRUE(d.capabilities.can_get_and_set_state);
  EXPECT_TRUE(d.capabilities.can_handle_variable_step);
  EXPECT_FALSE(d.capabilities.can_interpolate_inputs);
  EXPECT_EQ(d.capabilities.max_output_derivative_order, 0);
  ASSERT_EQ(d.variables.size(), 5u);
  EXPECT_EQ(d.find("steps")->type, "Integer");
  EXPECT_EQ(d.find("settled")->type, "Boolean");
  const Variable* k = d.find("k");
  ASSERT_NE(k, nullptr);
  EXPECT_EQ(k->value_reference, 1u);
  EXPECT_EQ(k->causality, "parameter");
  EXPECT_EQ(k->variability, "fixed");
  EXPECT_EQ(k->type, "Real");
  EXPECT_EQ(k->start, 1.0);
  EXPECT_EQ(k->unit, "1/s");
  EXPECT_EQ(d.find("u")->causality, "input");
  EXPECT_EQ(d.default_experiment.stop_time, 10.0);
  EXPECT_EQ(d.default_experiment.step_size, 0.1);
  EXPECT_FALSE(d.default_experiment.tolerance.has_value());
  EXPECT_FALSE(
      read_model_description(kFmus + "dahlquist2_nostate.xml").capabilities.can_get_and_set_state);
}

TEST(FmuDescription, ReadsTheFmi3TestFmu) {
  const ModelDescription d = read_model_description(kFmus + "dahlquist3.xml");
  EXPECT_EQ(d.version, FmiVersion::k3);
  EXPECT_EQ(d.model_identifier, "dahlquist3");
  EXPECT_EQ(d.token, "{railcosim-dahlquist3}");
  EXPECT_TRUE(d.capabilities.can_get_and_set_state);
  EXPECT_EQ(d.capabilities.fixed_internal_step, 0.1);
  ASSERT_EQ(d.variables.size(), 5u);
  EXPECT_EQ(d.variables[3].type, "Int32");
  EXPECT_EQ(d.variables[4].type, "Boolean");
  EXPECT_EQ(d.variables[0].name, "x");
  EXPECT_EQ(d.variables[0].type, "Float64");
  EXPECT_TRUE(d.variables[0].is_real());
  EXPECT_EQ(d.variables[0].start, 1.0);
  EXPECT_EQ(d.variables[0].unit, "m");
  EXPECT_EQ(d.variables[2].value_reference, 2u);
}

TEST(FmuDescription, RefusesModelExchangeOnlyAndOtherVersions) {
  std::string m = refusal(R"(<fmiModelDescription fmiVersion="2.0" guid="g">
      <ModelExchange modelIdentifier="m"/><ModelVariables/></fmiModelDescription>)");
  EXPECT_NE(m.find("test.xml: the FMU offers model exchange only; the host serves "
                   "co-simulation FMUs"),
            std::string::npos)
      << m;
  m = refusal(R"(<fmiModelDescription fmiVersion="1.0"><CoSimulation/></fmiModelDescription>)");
  EXPECT_NE(m.find("fmiVersion=\"1.0\": only FMI 2.0 and 3.0 are served"), std::string::npos);
  EXPECT_NE(refusal("<fmiModelDescription").find("test.xml: is not XML"), std::string::npos);
  m = refusal(R"(<fmiModelDescription fmiVersion="3.0">
      <CoSimulation modelIdentifier="../evil"/></fmiModelDescription>)");
  EXPECT_NE(m.find("modelIdentifier=\"../evil\" is not a plain file name"), std::string::npos);
}

TEST(FmuDescription, RefusesValuesThatAreNotNumbers) {
  std::string m = refusal(fmi3(R"(<Float64 name="x" valueReference="0" start="1.5e"/>)"));
  EXPECT_NE(m.find("<Float64> start=\"1.5e\" is not a number"), std::string::npos) << m;
  m = refusal(fmi3(R"(<Float64 name="x" valueReference="-1"/>)"));
  EXPECT_NE(m.find("valueReference=\"-1\" is not an unsigned 32-bit number"), std::string::npos);
  m = refusal(fmi2(R"(<ScalarVariable name="x" valueReference="0"/>)"));
  EXPECT_NE(m.find("variable 'x' has no type element"), std::string::npos) << m;
}

TEST(FmuDescription, RefusesTwoVariablesWithOneValueReference) {
  std::string m = refusal(fmi3(R"(<Float64 name="x" valueReference="7"/>
                                  <Int32 name="n" valueReference="7"/>)"));
  EXPECT_NE(m.find("variables 'x' and 'n' have the same valueReference 7"), std::string::npos) << m;
  m = refusal(fmi2(kReal2 + R"(<ScalarVariable name="n" valueReference="0"><Integer/>
                               </ScalarVariable>)"));
  EXPECT_NE(m.find("variables 'x' and 'n' have the same valueReference 0"), std::string::npos);
  // FMI 2.0 aliases of one type share a reference.
  EXPECT_NO_THROW(parse_model_description(
      fmi2(kReal2 + R"(<ScalarVariable name="y" valueReference="0"><Real/></ScalarVariable>)"),
      "test.xml"));
}

TEST(FmuDescription, RefusesReferencesToVariablesThatDoNotExist) {
  std::string m = refusal(fmi2(kReal2, R"(<Outputs><Unknown index="2"/></Outputs>)"));
  EXPECT_NE(m.find("<ModelStructure> <Unknown> index 2 names no variable (there are 1)"),
            std::string::npos)
      << m;
  m = refusal(fmi2(kReal2, R"(<Outputs><Unknown index="1" dependencies="1 3"/></Outputs>)"));
  EXPECT_NE(m.find("<Unknown> depends on 3 names no variable"), std::string::npos) << m;
  m = refusal(fmi3(R"(<Float64 name="x" valueReference="4"/>)", R"(<Output valueReference="5"/>)"));
  EXPECT_NE(m.find("<ModelStructure> <Output> valueReference 5 names no variable"),
            std::string::npos)
      << m;
  EXPECT_NO_THROW(parse_model_description(
      fmi3(R"(<Float64 name="x" valueReference="4"/>)", R"(<Output valueReference="4"/>)"),
      "test.xml"));
}

TEST(FmuDescription, RefusesMoreVariablesThanTheBound) {
  DescriptionLimits limits;
  limits.max_variables = 2;
  const std::string m = refusal(fmi3(R"(<Float64 name="a" valueReference="0"/>
      <Float64 name="b" valueReference="1"/><Float64 name="c" valueReference="2"/>)"),
                                limits);
  EXPECT_NE(m.find("it declares more than 2 variables"), std::string::npos) << m;
}

}  // namespace fmu_description_test
