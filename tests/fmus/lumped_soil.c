/* The lumped soil of the shared model as an FMI co-simulation FMU, for
 * the lower side of the ss cut with exchanged motion (ss-xx): a soil mass
 * under each of N_POINTS sleepers on a spring and damper to the ground, tied
 * to its neighbours, loaded through the ballast (kb, cb) from the sleepers'
 * displacement w_i and velocity wd_i; it sends its masses' displacement
 * u_i and velocity ud_i. Newmark (beta = 1/4, gamma = 1/2) with micro_steps
 * equal micro steps per communication step, restarted at each step from the
 * acceleration consistent with the inputs; in initialization mode its
 * outputs are the static state for the inputs set. The same physics as the
 * C++ example examples/cpp_soil, written again in C with a tridiagonal
 * solve. Built as FMI 2.0 (FMI_VERSION=2) or 3.0 (FMI_VERSION=3); as FMI
 * 2.0 with INPUT_DERIVATIVES=1 it follows its inputs' first derivatives
 * over a step (fmi2SetRealInputDerivatives: the ballast load at the end of
 * each micro step from the ramped inputs), as the built-in soil follows a
 * ramp. The FMI types are declared here for this file alone. */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define EXPORT __attribute__((visibility("default")))
#define N N_POINTS
#ifndef WITH_STATE
#define WITH_STATE 1
#endif
#ifndef INPUT_DERIVATIVES
#define INPUT_DERIVATIVES 0
#endif

/* Value references: parameters 1-8, then the per-point blocks. */
enum { VR_MASS = 1, VR_K, VR_C, VR_KC, VR_CC, VR_KB, VR_CB, VR_MICRO };
enum { VR_W = 100, VR_WD = 1100, VR_U = 2100, VR_UD = 3100 };
enum { S_OK = 0, S_ERROR = 3 };

typedef struct {
  double p[9]; /* parameters by value reference */
  double w[N], wd[N];   /* inputs */
  double dw[N], dwd[N]; /* their first derivatives (INPUT_DERIVATIVES) */
  double u[N], v[N], a[N];
  double t;
  bool init_mode;
} Model;

typedef struct {
  Model m;
} Instance;

/* K, C as tridiagonal (diagonal d, off-diagonal o, the same on both sides). */
static void stiffness(const Model* m, double* d, double* o) {
  for (int i = 0; i < N; ++i) d[i] = m->p[VR_K] + m->p[VR_KB];
  for (int i = 0; i + 1 < N; ++i) {
    d[i] += m->p[VR_KC];
    d[i + 1] += m->p[VR_KC];
    o[i] = -m->p[VR_KC];
  }
}
static void damping(const Model* m, double* d, double* o) {
  for (int i = 0; i < N; ++i) d[i] = m->p[VR_C] + m->p[VR_CB];
  for (int i = 0; i + 1 < N; ++i) {
    d[i] += m->p[VR_CC];
    d[i + 1] += m->p[VR_CC];
    o[i] = -m->p[VR_CC];
  }
}
/* y = T x for the tridiagonal (d, o). */
static void multiply(const double* d, const double* o, const double* x, double* y) {
  for (int i = 0; i < N; ++i) {
    y[i] = d[i] * x[i];
    if (i > 0) y[i] += o[i - 1] * x[i - 1];
    if (i + 1 < N) y[i] += o[i] * x[i + 1];
  }
}
/* Solves T x = b (Thomas' algorithm; T is symmetric positive definite). */
static void solve(const double* d, const double* o, const double* b, double* x) {
  double c[N], r[N];
  c[0] = N > 1 ? o[0] / d[0] : 0;
  r[0] = b[0] / d[0];
  for (int i = 1; i < N; ++i) {
    const double den = d[i] - o[i - 1] * c[i - 1];
    c[i] = i + 1 < N ? o[i] / den : 0;
    r[i] = (b[i] - o[i - 1] * r[i - 1]) / den;
  }
  x[N - 1] = r[N - 1];
  for (int i = N - 2; i >= 0; --i) x[i] = r[i] - c[i] * x[i + 1];
}
static void load(const Model* m, double* f) {
  for (int i = 0; i < N; ++i) f[i] = m->p[VR_KB] * m->w[i] + m->p[VR_CB] * m->wd[i];
}
/* The load s seconds into the step, the inputs ramped by their derivatives. */
static void load_at(const Model* m, double s, double* f) {
  load(m, f);
  if (!INPUT_DERIVATIVES) return;
  for (int i = 0; i < N; ++i) f[i] += s * (m->p[VR_KB] * m->dw[i] + m->p[VR_CB] * m->dwd[i]);
}
/* The acceleration consistent with the inputs and the state. */
static void restart(Model* m) {
  double f[N], kd[N], ko[N], cd[N], co[N], ku[N], cv[N];
  load(m, f);
  stiffness(m, kd, ko);
  damping(m, cd, co);
  multiply(kd, ko, m->u, ku);
  multiply(cd, co, m->v, cv);
  for (int i = 0; i < N; ++i) m->a[i] = (f[i] - cv[i] - ku[i]) / m->p[VR_MASS];
}
static void statics(Model* m) {
  double f[N], kd[N], ko[N];
  load(m, f);
  stiffness(m, kd, ko);
  solve(kd, ko, f, m->u);
  memset(m->v, 0, sizeof m->v);
  restart(m);
}
static int step(Model* m, double t, double big_h) {
  const int steps = (int)m->p[VR_MICRO];
  if (steps < 1 || big_h <= 0) return S_ERROR;
  (void)t;
  const double h = big_h / steps, c0 = 1.0 / (0.25 * h * h), c1 = 0.5 / (0.25 * h);
  double kd[N], ko[N], cd[N], co[N], ed[N], eo[N], f[N];
  stiffness(m, kd, ko);
  damping(m, cd, co);
  for (int i = 0; i < N; ++i) ed[i] = kd[i] + c1 * cd[i] + c0 * m->p[VR_MASS];
  for (int i = 0; i + 1 < N; ++i) eo[i] = ko[i] + c1 * co[i];
  restart(m);
  load(m, f);
  for (int k = 0; k < steps; ++k) {
    if (INPUT_DERIVATIVES) load_at(m, (k + 1) * h, f);
    double pu[N], pv[N], rhs[N], cp[N], un[N];
    for (int i = 0; i < N; ++i) {
      pu[i] = m->u[i] + h * m->v[i] + (h * h * 0.25) * m->a[i];
      pv[i] = m->v[i] + (h * 0.5) * m->a[i];
    }
    double q[N];
    for (int i = 0; i < N; ++i) q[i] = c1 * pu[i] - pv[i];
    multiply(cd, co, q, cp);
    for (int i = 0; i < N; ++i) rhs[i] = f[i] + m->p[VR_MASS] * (c0 * pu[i]) + cp[i];
    solve(ed, eo, rhs, un);
    for (int i = 0; i < N; ++i) {
      m->a[i] = c0 * (un[i] - pu[i]);
      m->v[i] = pv[i] + (0.5 * h) * m->a[i];
      m->u[i] = un[i];
    }
  }
  m->t = t + big_h;
  return S_OK;
}

static double* slot(Model* m, uint32_t vr) {
  if (vr >= VR_MASS && vr <= VR_MICRO) return &m->p[vr];
  if (vr >= VR_W && vr < VR_W + N) return &m->w[vr - VR_W];
  if (vr >= VR_WD && vr < VR_WD + N) return &m->wd[vr - VR_WD];
  if (vr >= VR_U && vr < VR_U + N) return &m->u[vr - VR_U];
  if (vr >= VR_UD && vr < VR_UD + N) return &m->v[vr - VR_UD];
  return NULL;
}

/* The defaults of the parameters, by value reference. */
static void defaults(Model* m) {
  const double p[9] = {0, 699.6, 121.08e6, 341.9e3, 43.72e6, 0.0, 25.5e6, 40e3, 10};
  memcpy(m->p, p, sizeof p);
}
static int set_reals(Model* m, const uint32_t* vr, size_t n, const double* v) {
  for (size_t i = 0; i < n; ++i) {
    double* s = slot(m, vr[i]);
    if (s == NULL || vr[i] >= VR_U) return S_ERROR;
    *s = v[i];
  }
  return S_OK;
}
static int get_reals(Model* m, const uint32_t* vr, size_t n, double* v) {
  if (m->init_mode) statics(m);
  for (size_t i = 0; i < n; ++i) {
    const double* s = slot(m, vr[i]);
    if (s == NULL) return S_ERROR;
    v[i] = *s;
  }
  return S_OK;
}
static int save(void* c, void** s) {
  if (!WITH_STATE) return S_ERROR;
  Model* copy = *s != NULL ? *s : malloc(sizeof(Model));
  if (copy == NULL) return S_ERROR;
  *copy = ((Instance*)c)->m;
  *s = copy;
  return S_OK;
}
static int restore(void* c, void* s) {
  if (s == NULL) return S_ERROR;
  ((Instance*)c)->m = *(const Model*)s;
  return S_OK;
}
static int drop(void** s) {
  free(*s);
  *s = NULL;
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
  (void)resources, (void)visible, (void)logging;
  if (type != 1 || guid == NULL || strcmp(guid, MODEL_TOKEN) != 0) {
    if (cb != NULL && cb->logger != NULL)
      cb->logger(cb->env, name, S_ERROR, "error", "wrong type or guid %s", guid ? guid : "");
    return NULL;
  }
  Instance* c = calloc(1, sizeof(Instance));
  if (c != NULL) defaults(&c->m);
  return c;
}
EXPORT void fmi2FreeInstance(void* c) { free(c); }
EXPORT int fmi2SetupExperiment(void* c, int tol_defined, double tol, double start, int stop_defined,
                               double stop) {
  (void)tol_defined, (void)tol, (void)stop_defined, (void)stop;
  ((Instance*)c)->m.t = start;
  return S_OK;
}
EXPORT int fmi2EnterInitializationMode(void* c) {
  ((Instance*)c)->m.init_mode = true;
  return S_OK;
}
EXPORT int fmi2ExitInitializationMode(void* c) {
  Model* m = &((Instance*)c)->m;
  statics(m);
  m->init_mode = false;
  return S_OK;
}
EXPORT int fmi2Terminate(void* c) { (void)c; return S_OK; }
EXPORT int fmi2Reset(void* c) {
  memset(c, 0, sizeof(Instance));
  defaults(&((Instance*)c)->m);
  return S_OK;
}
EXPORT int fmi2SetReal(void* c, const unsigned* vr, size_t n, const double* v) {
  return set_reals(&((Instance*)c)->m, vr, n, v);
}
EXPORT int fmi2GetReal(void* c, const unsigned* vr, size_t n, double* v) {
  return get_reals(&((Instance*)c)->m, vr, n, v);
}
#if INPUT_DERIVATIVES
EXPORT int fmi2SetRealInputDerivatives(void* c, const unsigned* vr, size_t n, const int* order,
                                       const double* v) {
  Model* m = &((Instance*)c)->m;
  for (size_t i = 0; i < n; ++i) {
    if (order[i] != 1) return S_ERROR;
    if (vr[i] >= VR_W && vr[i] < VR_W + N)
      m->dw[vr[i] - VR_W] = v[i];
    else if (vr[i] >= VR_WD && vr[i] < VR_WD + N)
      m->dwd[vr[i] - VR_WD] = v[i];
    else
      return S_ERROR;
  }
  return S_OK;
}
#endif
EXPORT int fmi2DoStep(void* c, double t, double h, int no_set_prior) {
  (void)no_set_prior;
  return step(&((Instance*)c)->m, t, h);
}
EXPORT int fmi2GetFMUstate(void* c, void** s) { return save(c, s); }
EXPORT int fmi2SetFMUstate(void* c, void* s) { return restore(c, s); }
EXPORT int fmi2FreeFMUstate(void* c, void** s) {
  (void)c;
  return drop(s);
}
#else
typedef void (*Logger3)(void*, int, const char*, const char*);

EXPORT void* fmi3InstantiateCoSimulation(const char* name, const char* token,
                                         const char* resources, bool visible, bool logging,
                                         bool event_mode, bool early_return,
                                         const uint32_t* intermediate, size_t n_intermediate,
                                         void* env, Logger3 log, void* update) {
  (void)name, (void)resources, (void)visible, (void)logging, (void)intermediate;
  (void)n_intermediate, (void)update;
  if (token == NULL || strcmp(token, MODEL_TOKEN) != 0 || event_mode || early_return) {
    if (log != NULL) log(env, S_ERROR, "error", "wrong token, or a mode this FMU lacks");
    return NULL;
  }
  Instance* c = calloc(1, sizeof(Instance));
  if (c != NULL) defaults(&c->m);
  return c;
}
EXPORT void fmi3FreeInstance(void* c) { free(c); }
EXPORT int fmi3EnterInitializationMode(void* c, bool tol_defined, double tol, double start,
                                       bool stop_defined, double stop) {
  (void)tol_defined, (void)tol, (void)stop_defined, (void)stop;
  Model* m = &((Instance*)c)->m;
  m->t = start;
  m->init_mode = true;
  return S_OK;
}
EXPORT int fmi3ExitInitializationMode(void* c) {
  Model* m = &((Instance*)c)->m;
  statics(m);
  m->init_mode = false;
  return S_OK;
}
EXPORT int fmi3Terminate(void* c) { (void)c; return S_OK; }
EXPORT int fmi3SetFloat64(void* c, const uint32_t* vr, size_t n, const double* v, size_t nv) {
  return nv == n ? set_reals(&((Instance*)c)->m, vr, n, v) : S_ERROR;
}
EXPORT int fmi3GetFloat64(void* c, const uint32_t* vr, size_t n, double* v, size_t nv) {
  return nv == n ? get_reals(&((Instance*)c)->m, vr, n, v) : S_ERROR;
}
EXPORT int fmi3DoStep(void* c, double t, double h, bool no_set_prior, bool* event, bool* stop,
                      bool* early, double* last) {
  (void)no_set_prior;
  *event = *stop = *early = false;
  const int s = step(&((Instance*)c)->m, t, h);
  *last = ((Instance*)c)->m.t;
  return s;
}
EXPORT int fmi3GetFMUState(void* c, void** s) { return save(c, s); }
EXPORT int fmi3SetFMUState(void* c, void* s) { return restore(c, s); }
EXPORT int fmi3FreeFMUState(void* c, void** s) {
  (void)c;
  return drop(s);
}
#endif
