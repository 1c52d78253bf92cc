#include "remote/transport.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <stdexcept>

#include "log.hpp"
#include "remote/inproc_fmu.hpp"
#include "remote/remote_participant.hpp"

namespace railcosim::remote {

ParticipantFactory inproc_factory(const Scene& scene) {
  return [scene](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    if (auto fmu = inproc_fmu(scene, c)) return fmu;  // the scene's soil FMU
    return std::make_unique<Subsystem>(scene, c);
  };
}

std::string node_program(const std::string& role) {
  if (role == "vehicle" || role == "track" || role == "soil") return role + "_node";
  return "track_node";
}

std::string soil_python_path(const std::string& root, const std::string& user) {
  std::string out = root;
  std::size_t begin = 0;
  while (begin <= user.size()) {
    std::size_t end = user.find(':', begin);
    if (end == std::string::npos) end = user.size();
    // Only absolute entries: an empty one, ".", or any relative folder is
    // looked up from the working directory, where the user runs the master.
    if (end > begin && user[begin] == '/') out += ":" + user.substr(begin, end - begin);
    begin = end + 1;
  }
  return out;
}

LaunchCommand fe_soil_command(const FeSoilLaunch& fe, const std::string& token_file) {
  const char* override_dir = std::getenv("RAILCOSIM_FE_SOIL");
  const std::string root = override_dir != nullptr && *override_dir != '\0'
                               ? std::string(override_dir)
                               : std::string(RAILCOSIM_SOURCE_DIR);
  LaunchCommand c;
  const std::string module = fe.soil->module;
  std::string file = module;
  for (char& ch : file)
    if (ch == '.') ch = '/';
  c.name = std::string(fe.soil->title) + " (" + root + "/" + file + ".py" +
           (fe.ranks > 1 ? ", " + std::to_string(fe.ranks) + " MPI ranks" : "") + ")";
  if (fe.ranks > 1) c.argv = {"/usr/bin/mpirun", "-n", std::to_string(fe.ranks)};
  // -P: nothing from the working directory (a numpy.py where the user runs
  // the master) comes before the product's own folder on the module path;
  // the soil's package is found through PYTHONPATH alone.
  c.argv.insert(c.argv.end(), {"/usr/bin/python3", "-P", "-m", module, "--listen", "127.0.0.1:0"});
  if (!fe.output_dir.empty()) c.argv.insert(c.argv.end(), {"--output-dir", fe.output_dir});
  if (!fe.scene.empty()) c.argv.insert(c.argv.end(), {"--scene-file", fe.scene});
  if (!token_file.empty()) c.argv.insert(c.argv.end(), {"--token-file", token_file});
  const char* path = std::getenv("PYTHONPATH");
  c.env = {"PYTHONPATH=" + soil_python_path(root, path != nullptr ? path : ""),
           "PYTHONSAFEPATH=1",  // the same for any Python the soil starts
           // One thread per rank: the other participants share the cores.
           "OMP_NUM_THREADS=1", "OPENBLAS_NUM_THREADS=1",
           // Open MPI refuses root without these, and more ranks than cores
           // without the last.
           "OMPI_ALLOW_RUN_AS_ROOT=1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1",
           "OMPI_MCA_rmaps_base_oversubscribe=1",
           // Ranks waiting for each other yield the core (the master and the
           // other participants run beside them).
           "OMPI_MCA_mpi_yield_when_idle=1"};
  return c;
}

std::optional<std::chrono::milliseconds> reply_limit_override() {
  const char* text = std::getenv("RAILCOSIM_REPLY_SECONDS");
  if (text == nullptr || *text == '\0') return std::nullopt;
  char* end = nullptr;
  const double seconds = std::strtod(text, &end);
  if (*end != '\0' || !(seconds > 0.0 && seconds <= 86400.0))
    throw std::invalid_argument("RAILCOSIM_REPLY_SECONDS=" + std::string(text) +
                                ": expected the reply limit in seconds, in (0, 86400]");
  return std::chrono::milliseconds(std::lround(std::max(seconds * 1000.0, 1.0)));
}

LaunchCommand soil_check_command(const FeSoilLaunch& fe) {
  FeSoilLaunch one = fe;
  one.ranks = 1;
  one.output_dir.clear();
  LaunchCommand c = fe_soil_command(one, "");
  for (std::size_t k = 0; k + 1 < c.argv.size(); ++k)
    if (c.argv[k] == "--listen") {
      c.argv.erase(c.argv.begin() + static_cast<std::ptrdiff_t>(k),
                   c.argv.begin() + static_cast<std::ptrdiff_t>(k) + 2);
      break;
    }
  c.argv.emplace_back("--check-configure");
  return c;
}

const Address& NodePool::address(const std::string& role, const std::string& given_program) {
  auto it = nodes_.find(role);
  if (it == nodes_.end() && role == "soil" && fe_) {
    auto node = std::make_unique<LaunchedNode>(fe_soil_command(*fe_, token_file_), kFeSoilStart);
    logger("master")->debug("started {} ({} rank{}) on {}", fe_->soil->title, fe_->ranks,
                            fe_->ranks > 1 ? "s" : "", node->address().str());
    it = nodes_.emplace(role, std::move(node)).first;
  }
  if (it == nodes_.end()) {
    const std::string program = given_program.empty() ? node_program(role) : given_program;
    std::vector<std::string> extra;
    if (fe_) extra = {"--idle-timeout", std::to_string(kIdleBesideFeSoil.count())};
    auto node =
        std::make_unique<LaunchedNode>(program, std::chrono::seconds(10), "127.0.0.1:0",
                                       program == role + "_node" ? "" : role, token_file_, extra);
    logger("master")->debug("started {} for the {} participant on {}", program, role,
                            node->address().str());
    it = nodes_.emplace(role, std::move(node)).first;
  }
  return it->second->address();
}

namespace {

// The participants inside the master: the scene's own subsystems.
class InprocTransport final : public Transport {
 public:
  const char* name() const override { return kInprocTransport; }
  bool remote() const override { return false; }
  bool carries_waveforms() const override { return true; }
  ParticipantFactory factory(const Scene& scene, const TransportSetup&) const override {
    return inproc_factory(scene);
  }
};

// Each participant in a node process, reached over TCP: the node given for
// its role, or one the pool starts.
class TcpTransport final : public Transport {
 public:
  const char* name() const override { return kTcpTransport; }
  bool remote() const override { return true; }
  // On either data plane: relayed, or on the direct plane in lock step
  // (the master sends each Step its waveforms).
  bool carries_waveforms() const override { return true; }
  ParticipantFactory factory(const Scene& scene, const TransportSetup& setup) const override {
    if (setup.pool == nullptr) throw std::logic_error("the tcp transport needs a node pool");
    RemoteTimeouts base;
    if (setup.step_budget.count() > 0)
      base.step_budget = setup.step_budget;
    else if (scene.coupling.step_budget)
      base.step_budget = std::chrono::milliseconds(std::lround(*scene.coupling.step_budget * 1000));
    if (setup.step_deadline_floor.count() > 0)
      base.step_min = setup.step_deadline_floor;
    else if (scene.coupling.step_deadline_floor)
      base.step_min =
          std::chrono::milliseconds(std::lround(*scene.coupling.step_deadline_floor * 1000));
    base.step_max = std::max(base.step_max, base.step_min);
    const auto reply = reply_limit_override();
    return [scene, given = setup.given, pool = setup.pool, token = setup.token, base,
            reply](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
      const auto it = given.find(c.participant.role);
      // A participant the scene maps to an FMU is served by fmu_node, sent
      // the mapping at Configure.
      const std::string program = scene.fmu_mapping(c.participant.role).empty() ? "" : "fmu_node";
      const Address address =
          it != given.end() ? it->second : pool->address(c.participant.role, program);
      RemoteTimeouts timeouts = base;
      if (scene.started_soil() != nullptr && c.participant.parts.has(Component::kSoil))
        timeouts.reply = kFeSoilReply;  // a mesh or Green's functions to build
      if (reply) timeouts.reply = *reply;
      return std::make_unique<RemoteParticipant>(address, scene, c, timeouts, token);
    };
  }
};

const InprocTransport kInproc;
const TcpTransport kTcp;

// The transports, by name: a new one is a class above and a line here.
const Transport* const kTransports[] = {&kInproc, &kTcp};

// "inproc or tcp"
std::string names_text() {
  std::string text;
  for (const Transport* t : kTransports) {
    if (t != kTransports[0]) text += t == kTransports[std::size(kTransports) - 1] ? " or " : ", ";
    text += t->name();
  }
  return text;
}

}  // namespace

std::vector<std::string> transport_names() {
  std::vector<std::string> names;
  for (const Transport* t : kTransports) names.emplace_back(t->name());
  return names;
}

const Transport* find_transport(const std::string& name) {
  for (const Transport* t : kTransports)
    if (name == t->name()) return t;
  return nullptr;
}

const Transport& parse_transport(const std::string& name, const std::string& what) {
  if (const Transport* t = find_transport(name)) return *t;
  throw std::invalid_argument(what + ": unknown transport '" + name + "' (" + names_text() + ")");
}

bool is_remote_transport(const std::string& name) {
  const Transport* t = find_transport(name);
  return t != nullptr && t->remote();
}

std::string other_transport(const std::string& name) {
  if (is_remote_transport(name)) return kInproc.name();
  for (const Transport* t : kTransports)
    if (t->remote()) return t->name();
  throw std::logic_error("other_transport: no remote transport in the table");
}

void check_transport(const engine::CouplingOptions& o, const std::string& transport) {
  const Transport* t = find_transport(transport);
  if (engine::waveform_degree(o.inputs) >= 0 && (t == nullptr || !t->carries_waveforms()))
    throw std::invalid_argument("--inputs " + to_string(o.inputs) +
                                ": substep waveforms travel in process or over tcp (relayed "
                                "data plane), not over the " +
                                transport + " transport (use --transport " + names_text() + ")");
}

SceneTransport make_transport(const Transport& transport, const Scene& scene,
                              const TransportSetup& setup) {
  return {transport.name(), transport.factory(scene, setup)};
}

SceneTransport inproc_transport(const Scene& scene) {
  return make_transport(kInproc, scene);
}

SceneTransport tcp_transport(const Scene& scene, std::map<std::string, Address> given,
                             NodePool& pool, std::optional<std::string> token) {
  return make_transport(kTcp, scene, {std::move(given), &pool, std::move(token)});
}

}  // namespace railcosim::remote
