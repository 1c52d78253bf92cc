// The built-in vehicle (common/: vehicle_model, Subsystem) as an FMI 3.0
// co-simulation FMU: C entry points around the vehicle's Subsystem of the
// scene in the FMU's resources (resources/scene.toml) and of the case in
// resources/case.txt (one cut at the wheel/rail contact, e.g. wr-xx-jacobi).
// One communication step is one macro step of the scene (simulation.
// macro_step); the wheel/rail interface's quantities are variables:
//   inputs  wr_in_displacement (10), wr_in_velocity (11), wr_in_force (12)
//   outputs wr_out_displacement (20), wr_out_velocity (21), wr_out_force (22)
// of which the case uses those its interface receives and sends, and the
// vehicle's history channels at the last communication point, wheel_m (30)
// and contact_force_N (31). In
// initialization mode the outputs are the vehicle's statics for the inputs
// set; the state is the Subsystem's checkpoint. Any error is fmi3Error with
// the reason logged.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "cosim_case.hpp"
#include "model.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

#define FMU_EXPORT extern "C" __attribute__((visibility("default")))

namespace {

using railcosim::CouplingData;
using railcosim::InterfaceData;
using railcosim::Quantity;

enum : int { kOK = 0, kError = 3 };
using Logger = void (*)(void*, int, const char*, const char*);

struct Vehicle {
  void* env = nullptr;
  Logger log = nullptr;
  std::string resources;
  std::unique_ptr<railcosim::Scene> scene;
  std::unique_ptr<railcosim::Subsystem> sub;
  double macro_step = 0;
  double in[3] = {0, 0, 0};  // displacement, velocity, force
  std::vector<Quantity> receives, sends;
  bool init_mode = false;
  // The outputs are those of the inputs now set: no input was set since
  // they were computed (a step's end, initialization), so a read takes them
  // as they are.
  bool fresh = false;
  long next = 0;                // the next macro step
  CouplingData outputs;         // the last ones computed
  std::vector<double> history;  // wheel_m, contact_force_N at the last point

  int fail(const std::string& why) {
    if (log != nullptr) log(env, kError, "error", why.c_str());
    return kError;
  }
  CouplingData inputs() const {
    InterfaceData d;
    for (Quantity q : receives) {
      const double v = in[static_cast<int>(q)];
      (q == Quantity::kDisplacement ? d.displacement
       : q == Quantity::kVelocity   ? d.velocity
                                    : d.force) = {v};
    }
    return {d};
  }
};

std::string read_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Builds the vehicle's Subsystem from the resources; throws with the reason.
void build(Vehicle& v) {
  v.scene = std::make_unique<railcosim::Scene>(railcosim::load_scene(v.resources + "scene.toml"));
  std::string case_name = read_text(v.resources + "case.txt");
  while (!case_name.empty() && std::isspace(static_cast<unsigned char>(case_name.back())))
    case_name.pop_back();
  const auto parts = railcosim::partition(*v.scene, railcosim::parse_case(case_name));
  const railcosim::ParticipantSpec* vehicle = nullptr;
  for (const auto& p : parts)
    if (p.role == "vehicle") vehicle = &p;
  if (vehicle == nullptr || vehicle->interfaces.size() != 1)
    throw std::invalid_argument("case " + case_name + ": the vehicle has not one interface");
  const railcosim::InterfaceSpec& itf = vehicle->interfaces[0];
  const railcosim::Channels channels = railcosim::channels_of(*v.scene, vehicle->parts);
  if (channels.history != std::vector<std::string>{"wheel_m", "contact_force_N"})
    throw std::invalid_argument("the vehicle's history is not wheel_m, contact_force_N");
  if (railcosim::interface_points(*v.scene, itf) != 1)
    throw std::invalid_argument("the vehicle's interface has more than one point");
  v.receives = itf.receives();
  v.sends = itf.sends();
  v.macro_step = v.scene->macro_step;
  v.sub = std::make_unique<railcosim::Subsystem>(
      *v.scene, railcosim::subsystem_config(*v.scene, *vehicle, v.macro_step, v.scene->tolerance));
}

double output(const Vehicle& v, Quantity q) {
  const InterfaceData& d = v.outputs.at(0);
  const auto& a = q == Quantity::kDisplacement ? d.displacement
                  : q == Quantity::kVelocity   ? d.velocity
                                               : d.force;
  return a.empty() ? 0.0 : a[0];
}

// Runs `f`, turning an exception into fmi3Error with its message logged.
template <class F>
int guarded(void* c, F&& f) {
  Vehicle& v = *static_cast<Vehicle*>(c);
  try {
    f(v);
    return kOK;
  } catch (const std::exception& e) {
    return v.fail(e.what());
  }
}

}  // namespace

FMU_EXPORT void* fmi3InstantiateCoSimulation(const char*, const char* token, const char* resources,
                                             bool, bool, bool event_mode, bool early_return,
                                             const std::uint32_t*, std::size_t, void* env,
                                             Logger log, void*) {
  auto v = std::make_unique<Vehicle>();
  v->env = env;
  v->log = log;
  v->resources = resources != nullptr ? resources : "";
  if (token == nullptr || std::strcmp(token, MODEL_TOKEN) != 0 || event_mode || early_return) {
    v->fail("wrong instantiation token, or a mode this FMU lacks");
    return nullptr;
  }
  try {
    build(*v);
  } catch (const std::exception& e) {
    v->fail(e.what());
    return nullptr;
  }
  return v.release();
}
FMU_EXPORT void fmi3FreeInstance(void* c) {
  delete static_cast<Vehicle*>(c);
}
FMU_EXPORT int fmi3EnterInitializationMode(void* c, bool, double, double start, bool, double) {
  return guarded(c, [&](Vehicle& v) {
    if (start != 0) throw std::invalid_argument("the vehicle starts at t = 0");
    v.init_mode = true;
  });
}
FMU_EXPORT int fmi3ExitInitializationMode(void* c) {
  return guarded(c, [](Vehicle& v) {
    const railcosim::StepResult r = v.sub->initialize(v.inputs());
    v.outputs = r.outputs;
    v.history = r.history;
    v.init_mode = false;
    v.fresh = true;
  });
}
FMU_EXPORT int fmi3Terminate(void*) {
  return kOK;
}
FMU_EXPORT int fmi3SetFloat64(void* c, const std::uint32_t* vr, std::size_t n, const double* x,
                              std::size_t nx) {
  return guarded(c, [&](Vehicle& v) {
    if (n != nx) throw std::invalid_argument("fmi3SetFloat64: one value per reference");
    for (std::size_t i = 0; i < n; ++i) {
      if (vr[i] < 10 || vr[i] > 12)
        throw std::invalid_argument("fmi3SetFloat64: " + std::to_string(vr[i]) +
                                    " is not an input");
      v.in[vr[i] - 10] = x[i];
    }
    v.fresh = false;
  });
}
FMU_EXPORT int fmi3GetFloat64(void* c, const std::uint32_t* vr, std::size_t n, double* x,
                              std::size_t nx) {
  return guarded(c, [&](Vehicle& v) {
    if (n != nx) throw std::invalid_argument("fmi3GetFloat64: one value per reference");
    if (v.init_mode) {
      v.outputs = v.sub->statics(v.inputs());
    } else if (!v.fresh) {  // the outputs with the inputs now set (a force output depends on them)
      v.sub->set_inputs(v.next, v.inputs());
      v.outputs = v.sub->outputs();
      v.fresh = true;
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (vr[i] >= 10 && vr[i] <= 12)
        x[i] = v.in[vr[i] - 10];
      else if (vr[i] >= 20 && vr[i] <= 22)
        x[i] = output(v, static_cast<Quantity>(vr[i] - 20));
      else if (vr[i] >= 30 && vr[i] - 30 < v.history.size())
        x[i] = v.history[vr[i] - 30];
      else
        throw std::invalid_argument("fmi3GetFloat64: no variable " + std::to_string(vr[i]));
    }
  });
}
FMU_EXPORT int fmi3DoStep(void* c, double t, double h, bool, bool* event, bool* stop, bool* early,
                          double* last) {
  *event = *stop = *early = false;
  *last = t;
  return guarded(c, [&](Vehicle& v) {
    if (std::abs(h - v.macro_step) > 1e-12 * v.macro_step)
      throw std::invalid_argument("the communication step must be the scene's macro step, " +
                                  std::to_string(v.macro_step) + " s");
    const long n = std::lround(t / v.macro_step);
    if (n != v.next)
      throw std::invalid_argument("a step from t = " + std::to_string(t) + " s, at macro step " +
                                  std::to_string(v.next));
    v.sub->set_inputs(n, v.inputs());
    const railcosim::StepResult r = v.sub->step(n);
    v.outputs = r.outputs;
    v.history = r.history;
    v.next = n + 1;
    v.fresh = true;
    *last = t + h;
  });
}
// A saved state: the Subsystem's checkpoint, the step it is at and the inputs.
struct Saved {
  railcosim::ParticipantState state;
  long next = 0;
  std::vector<double> history;
  double in[3] = {0, 0, 0};
};

FMU_EXPORT int fmi3GetFMUState(void* c, void** s) {
  return guarded(c, [&](Vehicle& v) {
    auto* saved = static_cast<Saved*>(*s);
    if (saved == nullptr) saved = new Saved;
    saved->state = v.sub->save();
    saved->next = v.next;
    saved->history = v.history;
    std::memcpy(saved->in, v.in, sizeof v.in);
    *s = saved;
  });
}
FMU_EXPORT int fmi3SetFMUState(void* c, void* s) {
  return guarded(c, [&](Vehicle& v) {
    if (s == nullptr) throw std::invalid_argument("fmi3SetFMUState: no state");
    const auto* saved = static_cast<const Saved*>(s);
    v.sub->restore(saved->state);
    v.next = saved->next;
    v.history = saved->history;
    std::memcpy(v.in, saved->in, sizeof v.in);
    v.fresh = false;
  });
}
FMU_EXPORT int fmi3FreeFMUState(void*, void** s) {
  delete static_cast<Saved*>(*s);
  *s = nullptr;
  return kOK;
}
