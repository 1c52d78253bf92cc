/* A co-simulation FMU of Dahlquist's test equation, x' = -k x + u, stepped
 * by forward Euler with h = 0.1 inside each communication step:
 * x <- (1 - k h) x + h u. With k = 1, u = 0 and x(0) = 1 it reaches
 * x(10) = 0.9^100 after 100 steps, the same products a test forms itself.
 * Built by CMake as FMI 2.0 (FMI_VERSION=2) or 3.0 (FMI_VERSION=3), with
 * state save and restore or without (WITH_STATE=0), or with a restore that
 * keeps x as it is (FORGETFUL_RESTORE=1, a broken FMU). The FMI types are
 * declared here, as the standard defines them, for this file alone. */
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define EXPORT __attribute__((visibility("default")))

#ifndef WITH_STATE
#define WITH_STATE 1
#endif

/* Beside x: `steps`, the communication steps taken (an Integer / Int32),
 * and `settled`, whether x < 1e-3 (a Boolean): after n steps of 0.1 s,
 * steps = n and settled = (0.9^n < 1e-3), true from n = 66 on. */
enum { VR_X = 0, VR_K = 1, VR_U = 2, VR_STEPS = 3, VR_SETTLED = 4 };
static const double kH = 0.1;

typedef struct {
  double x, k, u, t;
  int steps;
} Model;

typedef struct {
  Model m;
  void* env;
  void* log; /* the host's logger, by version */
} Instance;

enum { S_OK = 0, S_ERROR = 3 };

static int set_value(Model* m, unsigned vr, double v) {
  switch (vr) {
    case VR_X:
      m->x = v;
      return S_OK;
    case VR_K:
      m->k = v;
      return S_OK;
    case VR_U:
      m->u = v;
      return S_OK;
    default:
      return S_ERROR;
  }
}

static int get_value(const Model* m, unsigned vr, double* v) {
  switch (vr) {
    case VR_X:
      *v = m->x;
      return S_OK;
    case VR_K:
      *v = m->k;
      return S_OK;
    case VR_U:
      *v = m->u;
      return S_OK;
    default:
      return S_ERROR;
  }
}

/* One communication step of n Euler steps; H must be a multiple of h. */
static int step(Model* m, double t, double big_h) {
  const double n = round(big_h / kH);
  if (n < 1 || fabs(n * kH - big_h) > 1e-9 * big_h || fabs(t - m->t) > 1e-9 * (1 + fabs(t)))
    return S_ERROR;
  for (long i = 0; i < (long)n; ++i) m->x = (1 - m->k * kH) * m->x + kH * m->u;
  m->t = t + big_h;
  m->steps += 1;
  return S_OK;
}

static int get_discrete(const Model* m, unsigned vr, long* v) {
  switch (vr) {
    case VR_STEPS:
      *v = m->steps;
      return S_OK;
    case VR_SETTLED:
      *v = m->x < 1e-3;
      return S_OK;
    default:
      return S_ERROR;
  }
}

/* Built with STOP_AT=T, the FMU ends the simulation once it reaches T:
 * FMI 2 fmi2Discard with fmi2Terminated, FMI 3 terminateSimulation. */
static int ends(const Model* m) {
#ifdef STOP_AT
  return m->t >= STOP_AT - 1e-9;
#else
  (void)m;
  return 0;
#endif
}

static Instance* make(void) {
  Instance* c = calloc(1, sizeof(Instance));
  if (c != NULL) {
    c->m.x = 1;
    c->m.k = 1;
    c->m.u = 0;
  }
  return c;
}

static int save(Instance* c, void** state) {
  if (!WITH_STATE) return S_ERROR;
  Model* s = *state != NULL ? *state : malloc(sizeof(Model));
  if (s == NULL) return S_ERROR;
  *s = c->m;
  *state = s;
  return S_OK;
}

static int restore(Instance* c, void* state) {
  if (!WITH_STATE || state == NULL) return S_ERROR;
#ifdef FORGETFUL_RESTORE
  const double x = c->m.x;
  c->m = *(const Model*)state;
  c->m.x = x;
#else
  c->m = *(const Model*)state;
#endif
  return S_OK;
}

static int drop(void** state) {
  if (!WITH_STATE) return S_ERROR;
  free(*state);
  *state = NULL;
  return S_OK;
}

#if FMI_VERSION == 2
typedef void (*Logger2)(void*, const char*, int, const char*, const char*, ...);
typedef struct {
  Logger2 logger;
  void* (*allocate)(size_t, size_t);
  void (*release)(void*);
  void (*step_finished)(void*, int);
  void* env;
} Callbacks2;

EXPORT void* fmi2Instantiate(const char* name, int type, const char* guid, const char* resources,
                             const Callbacks2* cb, int visible, int logging) {
  (void)name, (void)resources, (void)visible, (void)logging;
  if (type != 1 || guid == NULL || strcmp(guid, MODEL_TOKEN) != 0) {
    if (cb != NULL && cb->logger != NULL)
      cb->logger(cb->env, name, S_ERROR, "error", "wrong type or guid %s", guid ? guid : "");
    return NULL;
  }
  Instance* c = make();
  if (c != NULL && cb != NULL) c->env = cb->env;
  return c;
}
EXPORT void fmi2FreeInstance(void* c) {
  free(c);
}
EXPORT int fmi2SetupExperiment(void* c, int tol_defined, double tol, double start, int stop_defined,
                               double stop) {
  (void)tol_defined, (void)tol, (void)stop_defined, (void)stop;
  ((Instance*)c)->m.t = start;
  return S_OK;
}
EXPORT int fmi2EnterInitializationMode(void* c) {
  (void)c;
  return S_OK;
}
EXPORT int fmi2ExitInitializationMode(void* c) {
  (void)c;
  return S_OK;
}
EXPORT int fmi2Terminate(void* c) {
  (void)c;
  return S_OK;
}
EXPORT int fmi2Reset(void* c) {
  Instance* i = c;
  Model m = {1, 1, 0, 0, 0};
  i->m = m;
  return S_OK;
}
EXPORT int fmi2SetReal(void* c, const unsigned* vr, size_t n, const double* v) {
  for (size_t i = 0; i < n; ++i)
    if (set_value(&((Instance*)c)->m, vr[i], v[i]) != S_OK) return S_ERROR;
  return S_OK;
}
EXPORT int fmi2GetReal(void* c, const unsigned* vr, size_t n, double* v) {
  for (size_t i = 0; i < n; ++i)
    if (get_value(&((Instance*)c)->m, vr[i], &v[i]) != S_OK) return S_ERROR;
  return S_OK;
}
EXPORT int fmi2GetInteger(void* c, const unsigned* vr, size_t n, int* v) {
  for (size_t i = 0; i < n; ++i) {
    long x = 0;
    if (vr[i] != VR_STEPS || get_discrete(&((Instance*)c)->m, vr[i], &x) != S_OK) return S_ERROR;
    v[i] = (int)x;
  }
  return S_OK;
}
EXPORT int fmi2GetBoolean(void* c, const unsigned* vr, size_t n, int* v) {
  for (size_t i = 0; i < n; ++i) {
    long x = 0;
    if (vr[i] != VR_SETTLED || get_discrete(&((Instance*)c)->m, vr[i], &x) != S_OK) return S_ERROR;
    v[i] = (int)x;
  }
  return S_OK;
}
EXPORT int fmi2DoStep(void* c, double t, double h, int no_set_prior) {
  (void)no_set_prior;
  const int s = step(&((Instance*)c)->m, t, h);
  return s == S_OK && ends(&((Instance*)c)->m) ? 2 /* fmi2Discard */ : s;
}
EXPORT int fmi2GetBooleanStatus(void* c, int kind, int* v) {
  if (kind != 3 /* fmi2Terminated */) return S_ERROR;
  *v = ends(&((Instance*)c)->m);
  return S_OK;
}
EXPORT int fmi2GetRealStatus(void* c, int kind, double* v) {
  if (kind != 2 /* fmi2LastSuccessfulTime */) return S_ERROR;
  *v = ((Instance*)c)->m.t;
  return S_OK;
}
EXPORT int fmi2GetFMUstate(void* c, void** s) {
  return save(c, s);
}
EXPORT int fmi2SetFMUstate(void* c, void* s) {
  return restore(c, s);
}
EXPORT int fmi2FreeFMUstate(void* c, void** s) {
  (void)c;
  return drop(s);
}
#else
typedef void (*Logger3)(void*, int, const char*, const char*);

EXPORT void* fmi3InstantiateCoSimulation(const char* name, const char* token, const char* resources,
                                         bool visible, bool logging, bool event_mode,
                                         bool early_return, const uint32_t* intermediate,
                                         size_t n_intermediate, void* env, Logger3 log,
                                         void* update) {
  (void)name, (void)resources, (void)visible, (void)logging, (void)intermediate;
  (void)n_intermediate, (void)update;
  if (token == NULL || strcmp(token, MODEL_TOKEN) != 0 || event_mode || early_return) {
    if (log != NULL) log(env, S_ERROR, "error", "wrong token, or a mode this FMU lacks");
    return NULL;
  }
  Instance* c = make();
  if (c != NULL) c->env = env;
  return c;
}
EXPORT void fmi3FreeInstance(void* c) {
  free(c);
}
EXPORT int fmi3EnterInitializationMode(void* c, bool tol_defined, double tol, double start,
                                       bool stop_defined, double stop) {
  (void)tol_defined, (void)tol, (void)stop_defined, (void)stop;
  ((Instance*)c)->m.t = start;
  return S_OK;
}
EXPORT int fmi3ExitInitializationMode(void* c) {
  (void)c;
  return S_OK;
}
EXPORT int fmi3Terminate(void* c) {
  (void)c;
  return S_OK;
}
EXPORT int fmi3SetFloat64(void* c, const uint32_t* vr, size_t n, const double* v, size_t nv) {
  if (nv != n) return S_ERROR;
  for (size_t i = 0; i < n; ++i)
    if (set_value(&((Instance*)c)->m, vr[i], v[i]) != S_OK) return S_ERROR;
  return S_OK;
}
EXPORT int fmi3GetFloat64(void* c, const uint32_t* vr, size_t n, double* v, size_t nv) {
  if (nv != n) return S_ERROR;
  for (size_t i = 0; i < n; ++i)
    if (get_value(&((Instance*)c)->m, vr[i], &v[i]) != S_OK) return S_ERROR;
  return S_OK;
}
EXPORT int fmi3GetInt32(void* c, const uint32_t* vr, size_t n, int32_t* v, size_t nv) {
  if (nv != n) return S_ERROR;
  for (size_t i = 0; i < n; ++i) {
    long x = 0;
    if (vr[i] != VR_STEPS || get_discrete(&((Instance*)c)->m, vr[i], &x) != S_OK) return S_ERROR;
    v[i] = (int32_t)x;
  }
  return S_OK;
}
EXPORT int fmi3GetBoolean(void* c, const uint32_t* vr, size_t n, bool* v, size_t nv) {
  if (nv != n) return S_ERROR;
  for (size_t i = 0; i < n; ++i) {
    long x = 0;
    if (vr[i] != VR_SETTLED || get_discrete(&((Instance*)c)->m, vr[i], &x) != S_OK) return S_ERROR;
    v[i] = x != 0;
  }
  return S_OK;
}
EXPORT int fmi3DoStep(void* c, double t, double h, bool no_set_prior, bool* event, bool* stop,
                      bool* early, double* last) {
  (void)no_set_prior;
  *event = false;
  *stop = false;
  *early = false;
  const int s = step(&((Instance*)c)->m, t, h);
  *last = ((Instance*)c)->m.t;
  *stop = s == S_OK && ends(&((Instance*)c)->m);
  return s;
}
EXPORT int fmi3GetFMUState(void* c, void** s) {
  return save(c, s);
}
EXPORT int fmi3SetFMUState(void* c, void* s) {
  return restore(c, s);
}
EXPORT int fmi3FreeFMUState(void* c, void** s) {
  (void)c;
  return drop(s);
}
#endif
