/* Follower forces on the particles of an elasto-active chain, as a MuJoCo passive callback.

   Every site with a non-zero first user value s->user[0] = F carries a force of magnitude F
   along minus its own x axis (the pendulum's direction, pointing back toward the anchor):
       f = -F (1 + eta) x_site .
   eta is optional multiplicative noise. The callback acts only on models that carry the custom
   numeric "elastoactive_follower" = (noise amplitude a, seed[, correlation time tau_c]), so other
   models in the process are left alone; the draws are the counter-based ones of
   controllers/noise.py, so both engines see the same noise.

   White noise (tau_c = 0 or absent): eta = a xi(seed, k, p) / sqrt(dt) over step k (k = the nearest
   whole number to time / dt).

   Coloured noise (tau_c > 0): eta is an Ornstein-Uhlenbeck process per particle (variance
   a^2 / (2 tau_c), correlation time tau_c), updated once per step by the exact discretisation
       eta_0 = sqrt(var) xi(seed, UINT64_MAX, p),  eta_{k+1} = e eta_k + sqrt(var (1 - e^2)) xi(seed, k, p)
   (e = exp(-dt / tau_c)); step k applies eta_k. The state lives in mjData.userdata (the model has
   nuserdata >= 1 + P for P particles): userdata[0] = k + 1 for the step k whose eta is held
   (0: none yet), userdata[1 + p] = eta_k of particle p. The step of a call is
   k = floor(time / dt + 1e-6): every call within one step (mj_forward, the implicit integrators'
   one call, RK4's stages at t and t + dt/2) reads the held values; a call in a later step advances
   them, one update per step in order (so RK4's last stage, at t + dt, takes eta_{k+1}: the noise
   is a piecewise-constant function of time). A call at an earlier step restarts from eta_0. eta_k is
   therefore a function of (seed, k) alone, and copies of mjData (mj_copyData, mjSTATE_INTEGRATION,
   which holds userdata) continue the same realisation.

   A periodic drive (the tip-drive term): with the custom numeric "elastoactive_drive" = (A, omega,
   d_x, d_y), every site whose second user value s->user[1] is non-zero also carries the force
   A sin(omega t) (d_x, d_y, 0), t = mjData.time of the call.

   Self-aligning active units (the self-aligning term; generic over sites: a particle on a chain's link or a
   lattice node that is a body on two slide joints). A site carrying a force (user[0] = F != 0) is a
   self-aligning unit when an actuator marks it:
       dyntype user (mjDYN_USER), one activation; transmission on the site (trntype site, target = the site), or,
       for a site on a body that slides (a lattice node), on one of that body's slide joints (trntype joint: the
       unit's site is then the site of the joint's body that carries a force; MuJoCo computes a joint transmission's
       moment in O(1), a site's as a Jacobian, which the unit, having no gain, does not need);
       dynprm[0] = l_a > 0, the alignment length; gain and bias 0 (gaintype fixed, gainprm[0] = 0, biastype none),
       so the actuator applies no force of its own; by convention named "<site name>_polarity".
   Its activation act = psi is the unit's polarity, an absolute angle in the lab's xy plane, integrated by MuJoCo
   (state: mjData.act, part of mjSTATE_INTEGRATION, so rollout and copies carry it). The act_dyn callback
   (self_aligning_act_dyn, installed as mjcb_act_dyn) returns
       dpsi/dt = (v . n_perp) / l_a,   n_perp = (-sin psi, cos psi, 0),
   v the site's lab-frame velocity (from mjData.cvel about the subtree centre of mass); the passive callback applies
   the unit's force F (1 + eta) (cos psi, sin psi, 0) at the site instead of -F (1 + eta) x_site. Actuators
   without the mark get act_dot = 0 from the callback; it acts only on models that carry elastoactive_follower.

   The forces are turned into generalised forces in one pass from the leaves to the root:
   each body collects the total force F_b and moment M_b (about the world origin) of the
   sites in its subtree; a hinge joint with anchor a and axis e then receives
   e . (M_b - a x F_b), a slide joint e . F_b. This is J^T f, computed in O(nbody).
   Other joint types receive nothing (the scenes use hinges only).

   The function touches only mjModel/mjData fields, so it needs MuJoCo's headers and not its
   library; it must be compiled against the same MuJoCo version it runs with (checked on load). */

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <mujoco/mujoco.h>

static uint64_t splitmix64(uint64_t x) {
  uint64_t z = x + 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

static double standard_normal(uint64_t seed, uint64_t step, uint64_t particle) {
  uint64_t key = splitmix64(splitmix64(seed) ^ step);
  double u1 = (double)(splitmix64(key + 2 * particle) >> 11) * 0x1.0p-53;
  double u2 = (double)(splitmix64(key + 2 * particle + 1) >> 11) * 0x1.0p-53;
  return sqrt(-2.0 * log1p(-u1)) * cos(2.0 * M_PI * u2);
}

static void cross3(mjtNum r[3], const mjtNum a[3], const mjtNum b[3]) {
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
}

static mjtNum dot3(const mjtNum a[3], const mjtNum b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* per-thread scratch: 6 numbers per body */
/* a force f at site s: onto its body's force, and its moment about the origin onto the body's moment */
static inline void add_site_force(const mjModel* m, const mjData* d, int s, const mjtNum f[3], mjtNum* force,
                                  mjtNum* moment) {
  mjtNum mo[3];
  cross3(mo, d->site_xpos + 3 * s, f);
  int b = m->site_bodyid[s];
  for (int k = 0; k < 3; k++) {
    force[3 * b + k] += f[k];
    moment[3 * b + k] += mo[k];
  }
}

static _Thread_local mjtNum* scratch = NULL;
static _Thread_local int scratch_bodies = 0;

static const mjtNum* find_numeric(const mjModel* m, const char* name, int size) {
  for (int i = 0; i < m->nnumeric; i++) {
    if (m->numeric_size[i] >= size && strcmp(m->names + m->name_numericadr[i], name) == 0) {
      return m->numeric_data + m->numeric_adr[i];
    }
  }
  return NULL;
}

/* The coloured noise of step `step` for `count` particles, in d->userdata (see the top of the file);
   returns the array of eta (userdata + 1), or NULL when the model holds no room for it. */
static const mjtNum* coloured_noise(const mjModel* m, mjData* d, const mjtNum* params, int count) {
  if (m->nuserdata < 1 + count) return NULL;
  double dt = m->opt.timestep, amplitude = params[0], tau_c = params[2];
  uint64_t seed = (uint64_t)params[1];
  double var = amplitude * amplitude / (2.0 * tau_c);
  double decay = exp(-dt / tau_c);
  double std = sqrt(var), kick = sqrt(var * (1.0 - decay * decay));
  double where = floor(d->time / dt + 1e-6);
  uint64_t step = where > 0 ? (uint64_t)where : 0;
  mjtNum* eta = d->userdata + 1;
  double held = d->userdata[0] - 1.0;
  if (held < 0 || (double)step < held) {
    for (int p = 0; p < count; p++) eta[p] = std * standard_normal(seed, UINT64_MAX, (uint64_t)p);
    held = 0;
  }
  for (uint64_t k = (uint64_t)held; k < step; k++) {
    for (int p = 0; p < count; p++) eta[p] = decay * eta[p] + kick * standard_normal(seed, k, (uint64_t)p);
  }
  d->userdata[0] = (double)step + 1.0;
  return eta;
}

/* ---- self-aligning units (see the top of the file) ---- */

static int is_self_aligning_unit(const mjModel* m, int a) {
  if (m->actuator_dyntype[a] != mjDYN_USER || m->actuator_dynprm[a * mjNDYN] <= 0 || m->actuator_actadr[a] < 0 ||
      m->actuator_trnid[2 * a] < 0) {
    return 0;
  }
  int trn = m->actuator_trntype[a];
  return trn == mjTRN_SITE || (trn == mjTRN_JOINT && m->jnt_type[m->actuator_trnid[2 * a]] == mjJNT_SLIDE);
}

/* the lab-frame linear velocity of site s: cvel's linear part (at the subtree centre of mass of the body's root)
   moved to the site */
static void site_velocity(const mjModel* m, const mjData* d, int s, mjtNum v[3]) {
  int b = m->site_bodyid[s];
  const mjtNum* c = d->subtree_com + 3 * m->body_rootid[b];
  const mjtNum* cv = d->cvel + 6 * b;
  const mjtNum* p = d->site_xpos + 3 * s;
  mjtNum r[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]}, wr[3];
  cross3(wr, cv, r);
  for (int k = 0; k < 3; k++) v[k] = cv[3 + k] + wr[k];
}

/* per thread, for the model last seen: per site, the activation address of the unit that marks it (-1: none), and
   per actuator, the site of the unit it is (-1: none) */
static _Thread_local int* unit_of_site = NULL;
static _Thread_local int* site_of_unit = NULL;
static _Thread_local int* scratch_site_of_body = NULL;
static _Thread_local const mjModel* units_model = NULL;
static _Thread_local int units_any = 0;

static _Thread_local int units_capacity = 0;

/* (re)builds the per-thread maps for m; returns whether m has a unit */
static int build_units(const mjModel* m) {
  units_model = NULL;
  units_any = 0;
  int need = m->nsite > m->nu ? m->nsite : m->nu;
  if (m->nbody > need) need = m->nbody;
  if (need < 1) need = 1;
  if (units_capacity < need) {
    int* a1 = (int*)realloc(unit_of_site, sizeof(int) * need);
    if (a1) unit_of_site = a1;
    int* a2 = (int*)realloc(site_of_unit, sizeof(int) * need);
    if (a2) site_of_unit = a2;
    int* a3 = (int*)realloc(scratch_site_of_body, sizeof(int) * need);
    if (a3) scratch_site_of_body = a3;
    if (!a1 || !a2 || !a3) return 0;
    units_capacity = need;
  }
  for (int b = 0; b < m->nbody; b++) scratch_site_of_body[b] = -1;
  for (int s = m->nsite - 1; s >= 0; s--) {
    if (m->nuser_site >= 1 && m->site_user[s * m->nuser_site] != 0) scratch_site_of_body[m->site_bodyid[s]] = s;
  }
  for (int s = 0; s < m->nsite; s++) unit_of_site[s] = -1;
  for (int a = 0; a < m->nu; a++) {
    int s = -1;
    if (is_self_aligning_unit(m, a)) {
      int target = m->actuator_trnid[2 * a];
      s = m->actuator_trntype[a] == mjTRN_SITE ? target : scratch_site_of_body[m->jnt_bodyid[target]];
    }
    site_of_unit[a] = s;
    if (s >= 0) {
      unit_of_site[s] = m->actuator_actadr[a];
      units_any = 1;
    }
  }
  units_model = m;
  return units_any;
}

static mjtNum self_aligning_act_dyn(const mjModel* m, const mjData* d, int id) {
  if (!is_self_aligning_unit(m, id) || !find_numeric(m, "elastoactive_follower", 2)) return 0;
  if (units_model != m && !build_units(m)) return 0;
  int s = site_of_unit[id];
  if (s < 0) return 0;
  mjtNum v[3];
  site_velocity(m, d, s, v);
  mjtNum psi = d->act[m->actuator_actadr[id]];
  return (-v[0] * sin(psi) + v[1] * cos(psi)) / m->actuator_dynprm[id * mjNDYN];
}

/* per site, the activation address of the self-aligning unit that marks it (-1: none); NULL when the model has
   no unit. Rebuilt at every call (the passive callback's, before the act_dyn callback's in each forward pass), so the
   act_dyn callback reads maps of the model being stepped. */
static const int* self_aligning_units(const mjModel* m) {
  return build_units(m) ? unit_of_site : NULL;
}

/* the active force of magnitude F at site s: along the unit's polarity, or the follower's -F x_site */
static inline void active_force(const mjData* d, const int* units, int s, mjtNum magnitude, mjtNum f[3]) {
  if (units && units[s] >= 0) {
    mjtNum psi = d->act[units[s]];
    f[0] = magnitude * cos(psi);
    f[1] = magnitude * sin(psi);
    f[2] = 0;
    return;
  }
  const mjtNum* R = d->site_xmat + 9 * s;
  f[0] = -magnitude * R[0];
  f[1] = -magnitude * R[3];
  f[2] = -magnitude * R[6];
}

/* A moving clamp (the moving-clamp term): with the custom numeric "elastoactive_clamp" = (A, omega, a_x, a_y,
   A_phi, K, B[, Omega]), chain 1's clamp follows x_c(t) = (a_x, a_y) sin(omega t) and its angle
   phi_c(t) = A_phi sin(omega t) + Omega t (Omega: a steadily rotating clamp's rate, 0 when absent).
   The point: the slide joints clamp_x and clamp_y (damped by -B q' from two velocity actuators on the clamp's site,
   integrated implicitly by MuJoCo) receive the servo force B u(t) + K (x_c(t) - q), u = x_c'; with the damping,
   -B (q' - u) + K (x_c - q) holds the clamp on its path. The angle: the hinge named by the custom text "elastoactive_clamp_hinge" receives
   C1 phi_c(t) (C1 = its stiffness), so its spring acts as C1 (theta_1 - phi_c). */
static int find_joint(const mjModel* m, const char* name) {
  for (int j = 0; j < m->njnt; j++) {
    if (strcmp(m->names + m->name_jntadr[j], name) == 0) return j;
  }
  return -1;
}

static const char* find_text(const mjModel* m, const char* name) {
  for (int i = 0; i < m->ntext; i++) {
    if (strcmp(m->names + m->name_textadr[i], name) == 0) return m->text_data + m->text_adr[i];
  }
  return NULL;
}

static void clamp_servo(const mjModel* m, mjData* d) {
  const mjtNum* c = find_numeric(m, "elastoactive_clamp", 7);
  const mjtNum* turning = find_numeric(m, "elastoactive_clamp", 8);
  mjtNum rate = turning ? turning[7] : 0;
  if (!c || (c[0] == 0 && rate == 0)) return;
  mjtNum s = sin(c[1] * d->time), u = c[1] * cos(c[1] * d->time);
  static const char* slides[2] = {"clamp_x", "clamp_y"};
  for (int k = 0; k < 2; k++) {
    int j = find_joint(m, slides[k]);
    if (j < 0) continue;
    int dof = m->jnt_dofadr[j];
    d->qfrc_passive[dof] += c[6] * c[2 + k] * u + c[5] * (c[2 + k] * s - d->qpos[m->jnt_qposadr[j]]);
  }
  const char* hinge = find_text(m, "elastoactive_clamp_hinge");
  int j = (hinge && (c[4] != 0 || rate != 0)) ? find_joint(m, hinge) : -1;
  if (j >= 0) d->qfrc_passive[m->jnt_dofadr[j]] += m->jnt_stiffness[j] * (c[4] * s + rate * d->time);
}

static void follower_passive(const mjModel* m, mjData* d) {
  if (m->nuser_site < 1) return;
  const mjtNum* params = find_numeric(m, "elastoactive_follower", 2);
  if (!params) return;
  clamp_servo(m, d);
  int coloured = 0;
  for (int i = 0; i < m->nnumeric; i++) {
    if (m->numeric_data + m->numeric_adr[i] == params) coloured = m->numeric_size[i] >= 3 && params[2] > 0;
  }
  int nbody = m->nbody;
  if (scratch_bodies < nbody) {
    mjtNum* grown = (mjtNum*)realloc(scratch, sizeof(mjtNum) * 6 * nbody);
    if (!grown) return;
    scratch = grown;
    scratch_bodies = nbody;
  }
  mjtNum* force = scratch;             /* 3 per body */
  mjtNum* moment = scratch + 3 * nbody; /* 3 per body */
  memset(scratch, 0, sizeof(mjtNum) * 6 * nbody);

  double amplitude = 0;
  uint64_t seed = 0, step = 0;
  const mjtNum* eta = NULL;
  if (coloured && params[0] > 0) {
    int count = 0;
    for (int s = 0; s < m->nsite; s++) count += m->site_user[s * m->nuser_site] != 0;
    eta = coloured_noise(m, d, params, count);
  } else if (params[0] > 0) {
    amplitude = params[0] / sqrt(m->opt.timestep);
    seed = (uint64_t)params[1];
    step = (uint64_t)llround(d->time / m->opt.timestep);
  }

  const int* units = self_aligning_units(m);
  int particle = 0, any = 0;
  for (int s = 0; s < m->nsite; s++) {
    mjtNum magnitude = m->site_user[s * m->nuser_site];
    if (magnitude == 0) continue;
    if (eta) {
      magnitude *= 1.0 + eta[particle];
    } else if (amplitude > 0) {
      magnitude *= 1.0 + amplitude * standard_normal(seed, step, (uint64_t)particle);
    }
    particle++;
    any = 1;
    mjtNum f[3];
    active_force(d, units, s, magnitude, f);
    add_site_force(m, d, s, f, force, moment);
  }
  const mjtNum* drive = find_numeric(m, "elastoactive_drive", 4);
  if (drive && drive[0] != 0 && m->nuser_site >= 2) {
    mjtNum now = drive[0] * sin(drive[1] * d->time);
    mjtNum f[3] = {now * drive[2], now * drive[3], 0};
    for (int s = 0; s < m->nsite; s++) {
      if (m->site_user[s * m->nuser_site + 1] == 0) continue;
      add_site_force(m, d, s, f, force, moment);
      any = 1;
    }
  }
  if (!any) return;

  /* bodies are stored parents first: sweep from the leaves to the root */
  for (int b = nbody - 1; b > 0; b--) {
    const mjtNum* fb = force + 3 * b;
    const mjtNum* mb = moment + 3 * b;
    for (int k = 0; k < m->body_jntnum[b]; k++) {
      int j = m->body_jntadr[b] + k;
      const mjtNum* axis = d->xaxis + 3 * j;
      if (m->jnt_type[j] == mjJNT_HINGE) {
        mjtNum axf[3];
        cross3(axf, d->xanchor + 3 * j, fb);
        d->qfrc_passive[m->jnt_dofadr[j]] += dot3(axis, mb) - dot3(axis, axf);
      } else if (m->jnt_type[j] == mjJNT_SLIDE) {
        d->qfrc_passive[m->jnt_dofadr[j]] += dot3(axis, fb);
      }
    }
    int parent = m->body_parentid[b];
    for (int k = 0; k < 3; k++) {
      force[3 * parent + k] += fb[k];
      moment[3 * parent + k] += mb[k];
    }
  }
}

/* ---- Python module: hands out the callback's address ---- */

static PyObject* passive_address(PyObject* self, PyObject* args) {
  return PyLong_FromVoidPtr((void*)&follower_passive);
}

static PyObject* act_dyn_address(PyObject* self, PyObject* args) {
  return PyLong_FromVoidPtr((void*)&self_aligning_act_dyn);
}

static PyObject* header_version(PyObject* self, PyObject* args) {
  return PyLong_FromLong(mjVERSION_HEADER);
}

static PyObject* py_standard_normal(PyObject* self, PyObject* args) {
  unsigned long long seed, step, particle;
  if (!PyArg_ParseTuple(args, "KKK", &seed, &step, &particle)) return NULL;
  return PyFloat_FromDouble(standard_normal(seed, step, particle));
}

static PyMethodDef methods[] = {
    {"passive_address", passive_address, METH_NOARGS, "Address of the C passive callback."},
    {"act_dyn_address", act_dyn_address, METH_NOARGS, "Address of the C act_dyn callback (self-aligning units)."},
    {"header_version", header_version, METH_NOARGS, "mjVERSION_HEADER this module was built with."},
    {"standard_normal", py_standard_normal, METH_VARARGS, "The callback's noise draw (seed, step, particle)."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_follower",
                                    "Compiled follower-force callback.", -1, methods};

PyMODINIT_FUNC PyInit__follower(void) { return PyModule_Create(&module); }
