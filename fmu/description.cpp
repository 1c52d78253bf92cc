#include "description.hpp"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <map>
#include <pugixml.hpp>
#include <sstream>

#include "fmu_error.hpp"

namespace railcosim::fmu {
namespace {

struct Reader {
  std::string where;
  const DescriptionLimits& limits;

  [[noreturn]] void refuse(const std::string& why) const { throw FmuError(where + ": " + why); }

  double number(const pugi::xml_node& n, const char* attr) const {
    const std::string text = n.attribute(attr).value();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || errno == ERANGE)
      refuse(std::string("<") + n.name() + "> " + attr + "=\"" + text + "\" is not a number");
    return v;
  }
  std::optional<double> optional_number(const pugi::xml_node& n, const char* attr) const {
    if (!n.attribute(attr)) return std::nullopt;
    return number(n, attr);
  }
  std::uint32_t unsigned_number(const pugi::xml_node& n, const char* attr) const {
    const std::string text = n.attribute(attr).value();
    char* end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
    if (text.empty() || text.front() == '-' || *end != '\0' || errno == ERANGE || v > 0xffffffffULL)
      refuse(std::string("<") + n.name() + "> " + attr + "=\"" + text +
             "\" is not an unsigned 32-bit number");
    return static_cast<std::uint32_t>(v);
  }
  bool flag(const pugi::xml_node& n, const char* attr) const {
    const std::string text = n.attribute(attr).value();
    if (text.empty() || text == "false") return false;
    if (text == "true") return true;
    refuse(std::string("<") + n.name() + "> " + attr + "=\"" + text + "\" is not true or false");
  }
  std::string name(const pugi::xml_node& n, const char* attr) const {
    std::string s = n.attribute(attr).value();
    if (s.size() > limits.max_name_bytes)
      refuse(std::string("<") + n.name() + "> " + attr + " is longer than " +
             std::to_string(limits.max_name_bytes) + " bytes");
    return s;
  }
};

Capabilities read_capabilities(const Reader& r, const pugi::xml_node& cs, FmiVersion v) {
  Capabilities c;
  const bool three = v == FmiVersion::k3;
  c.can_get_and_set_state = r.flag(cs, three ? "canGetAndSetFMUState" : "canGetAndSetFMUstate");
  c.can_serialize_state = r.flag(cs, three ? "canSerializeFMUState" : "canSerializeFMUstate");
  c.can_handle_variable_step = r.flag(cs, "canHandleVariableCommunicationStepSize");
  c.can_interpolate_inputs = !three && r.flag(cs, "canInterpolateInputs");
  c.provides_directional_derivatives =
      r.flag(cs, three ? "providesDirectionalDerivatives" : "providesDirectionalDerivative");
  c.needs_execution_tool = r.flag(cs, "needsExecutionTool");
  if (cs.attribute("maxOutputDerivativeOrder")) {
    const std::uint32_t order = r.unsigned_number(cs, "maxOutputDerivativeOrder");
    if (order > 16)
      r.refuse("<CoSimulation> maxOutputDerivativeOrder=" + std::to_string(order) +
               " is beyond any FMU's (at most 16 read)");
    c.max_output_derivative_order = static_cast<int>(order);
  }
  if (three) c.fixed_internal_step = r.optional_number(cs, "fixedInternalStepSize");
  return c;
}

// The FMI 2 <ScalarVariable> or FMI 3 typed element `n`.
Variable read_variable(const Reader& r, const pugi::xml_node& n, FmiVersion v) {
  Variable var;
  var.name = r.name(n, "name");
  if (var.name.empty()) r.refuse(std::string("a <") + n.name() + "> has no name");
  var.value_reference = r.unsigned_number(n, "valueReference");
  if (n.attribute("causality")) var.causality = n.attribute("causality").value();
  if (n.attribute("variability")) var.variability = n.attribute("variability").value();
  pugi::xml_node typed = n;
  if (v == FmiVersion::k2) {
    typed = n.first_child();
    while (typed && typed.type() != pugi::node_element) typed = typed.next_sibling();
    if (!typed) r.refuse("variable '" + var.name + "' has no type element");
    var.type = typed.name();
  } else {
    var.type = n.name();
    if (n.child("Dimension")) var.type += " array";  // arrays are read, not served
    for (const pugi::xml_node d : n.children("Dimension")) {
      Variable::Dimension dim;
      if (d.attribute("start")) dim.start = r.unsigned_number(d, "start");
      if (d.attribute("valueReference"))
        dim.value_reference = r.unsigned_number(d, "valueReference");
      if (!dim.start && !dim.value_reference)
        r.refuse("variable '" + var.name +
                 "' has a <Dimension> with neither start nor valueReference");
      var.dimensions.push_back(dim);
    }
  }
  var.unit = r.name(typed, "unit");
  if (var.is_real()) var.start = r.optional_number(typed, "start");
  return var;
}

// Every value reference names one variable (for each type, FMI 3 allows no
// sharing across types either), and every reference into the list exists.
void check_references(const Reader& r, const pugi::xml_node& root, const ModelDescription& d) {
  std::map<std::uint32_t, const Variable*> by_reference;
  for (const Variable& var : d.variables) {
    auto [it, fresh] = by_reference.emplace(var.value_reference, &var);
    // FMI 2 lets aliases of one type share a reference; never across types.
    const bool alias = d.version == FmiVersion::k2 && it->second->type == var.type;
    if (!fresh && !alias)
      r.refuse("variables '" + it->second->name + "' and '" + var.name +
               "' have the same valueReference " + std::to_string(var.value_reference));
  }
  // FMI 2 refers to variables by their 1-based index in the list, FMI 3 by
  // value reference: each <Unknown>/<Output>/... and its dependencies.
  const bool two = d.version == FmiVersion::k2;
  auto check = [&](const pugi::xml_node& u, const std::string& what, std::uint64_t ref) {
    const bool exists = two ? ref >= 1 && ref <= d.variables.size()
                            : by_reference.count(static_cast<std::uint32_t>(ref)) > 0;
    if (!exists)
      r.refuse("<ModelStructure> <" + std::string(u.name()) + "> " + what + " " +
               std::to_string(ref) + " names no variable (there are " +
               std::to_string(d.variables.size()) + ")");
  };
  auto check_unknown = [&](const pugi::xml_node& u) {
    const char* key = two ? "index" : "valueReference";
    check(u, key, r.unsigned_number(u, key));
    std::istringstream deps(u.attribute("dependencies").value());
    std::string dep;
    while (deps >> dep) {
      char* end = nullptr;
      const unsigned long long ref = std::strtoull(dep.c_str(), &end, 10);
      if (*end != '\0' || dep.front() == '-')
        r.refuse("<ModelStructure> <" + std::string(u.name()) + "> dependencies \"" + dep +
                 "\" is not a variable's reference");
      check(u, "depends on", ref);
    }
  };
  for (const pugi::xml_node& n : root.child("ModelStructure").children()) {
    if (n.type() != pugi::node_element) continue;
    if (!two) {
      check_unknown(n);
      continue;
    }
    for (const pugi::xml_node& u : n.children("Unknown")) check_unknown(u);
  }
}

}  // namespace

const char* version_name(FmiVersion v) {
  return v == FmiVersion::k2 ? "2.0" : "3.0";
}

const Variable* ModelDescription::find(const std::string& name) const {
  for (const Variable& v : variables)
    if (v.name == name) return &v;
  return nullptr;
}

ModelDescription parse_model_description(const std::string& text, const std::string& where,
                                         const DescriptionLimits& limits) {
  const Reader r{where, limits};
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size());
  if (!parsed)
    r.refuse(std::string("is not XML: ") + parsed.description() + " at byte " +
             std::to_string(parsed.offset));
  const pugi::xml_node root = doc.child("fmiModelDescription");
  if (!root) r.refuse("has no <fmiModelDescription> element");
  ModelDescription d;
  const std::string version = root.attribute("fmiVersion").value();
  if (version.rfind("2.", 0) == 0)
    d.version = FmiVersion::k2;
  else if (version.rfind("3.", 0) == 0)
    d.version = FmiVersion::k3;
  else
    r.refuse("fmiVersion=\"" + version + "\": only FMI 2.0 and 3.0 are served");
  d.model_name = r.name(root, "modelName");
  d.token = r.name(root, d.version == FmiVersion::k2 ? "guid" : "instantiationToken");
  const pugi::xml_node cs = root.child("CoSimulation");
  if (!cs)
    r.refuse(root.child("ModelExchange")
                 ? "the FMU offers model exchange only; the host serves co-simulation FMUs "
                   "(export it with a <CoSimulation> interface)"
                 : "it has no <CoSimulation> element: not a co-simulation FMU");
  d.model_identifier = r.name(cs, "modelIdentifier");
  if (d.model_identifier.empty() || d.model_identifier.find_first_of("/\\.") != std::string::npos)
    r.refuse("<CoSimulation> modelIdentifier=\"" + d.model_identifier +
             "\" is not a plain file name");
  d.capabilities = read_capabilities(r, cs, d.version);
  const pugi::xml_node list = root.child("ModelVariables");
  for (const pugi::xml_node& n : list.children()) {
    if (n.type() != pugi::node_element) continue;
    if (d.variables.size() == limits.max_variables)
      r.refuse("it declares more than " + std::to_string(limits.max_variables) + " variables");
    d.variables.push_back(read_variable(r, n, d.version));
  }
  check_references(r, root, d);
  if (const pugi::xml_node e = root.child("DefaultExperiment")) {
    d.default_experiment = {r.optional_number(e, "startTime"), r.optional_number(e, "stopTime"),
                            r.optional_number(e, "tolerance"), r.optional_number(e, "stepSize")};
  }
  return d;
}

ModelDescription read_model_description(const std::filesystem::path& file,
                                        const DescriptionLimits& limits) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  if (ec) throw FmuError(file.string() + ": cannot be read (" + ec.message() + ")");
  if (bytes > limits.max_file_bytes)
    throw FmuError(file.string() + ": " + std::to_string(bytes) + " bytes, more than the " +
                   std::to_string(limits.max_file_bytes) + " a description may have");
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return parse_model_description(text.str(), file.string(), limits);
}

std::optional<std::filesystem::path> reference_result(const std::filesystem::path& root) {
  const std::filesystem::path dir = root / "extra" / "org.fmi-standard.fmi-ls-ref";
  const std::filesystem::path manifest = dir / "fmi-ls-manifest.xml";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(manifest, ec)) return std::nullopt;
  pugi::xml_document doc;
  if (!doc.load_file(manifest.c_str()))
    throw FmuError(manifest.filename().string() + " of the FMU: not readable XML");
  for (const pugi::xml_node n : doc.document_element().children("Related")) {
    if (std::string(n.attribute("role").as_string()) != "result" ||
        std::string(n.attribute("type").as_string()) != "text/csv")
      continue;
    const std::string source = n.attribute("source").as_string();
    if (source.empty() || source.find('/') != std::string::npos || source == "." || source == "..")
      throw FmuError(
          "extra/org.fmi-standard.fmi-ls-ref/fmi-ls-manifest.xml of the FMU: the "
          "result's source '" +
          source + "' is not a file name in that folder");
    if (std::filesystem::is_regular_file(dir / source, ec)) return dir / source;
  }
  return std::nullopt;
}

}  // namespace railcosim::fmu
