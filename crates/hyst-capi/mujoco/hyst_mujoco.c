// MuJoCo actuator plugins over hyst's C API (docs/mujoco.md):
//
//   hyst.backlash     a position servo through the hysteresis: the target is H(k1, k2)[ctrl]
//                     (eq. 2), or the fitted model of ctrl when `model` names a model file;
//   hyst.compensator  the same servo with the exact inverse applied to ctrl first: the target
//                     is H⁻¹(k1, k2)[ctrl] (eq. 4), or the fitted model's inverse, the
//                     feed-forward a real controller runs before a gear with backlash.
//
// The force is kp (target − length) − kv velocity, in the actuator's units (its length is
// gear · qpos for a joint transmission). The operator's memory (Definition 2.1) lives in the
// actuator's activations, HYST_MUJOCO_ACTDIM of them, so mj_getState / mj_setState, keyframes,
// mj_resetData and finite differences all carry it: act = 0 is an operator with no history.
// Each step computes the new memory from act and ctrl in `actuator_act_dot` (act_dot = (new −
// act) / h), and `advance` then writes the new memory into act exactly, so act after mj_step is
// the memory hyst's own run holds, bit for bit. `plugin_state` holds, per actuator, that new
// memory and the step's target (HYST_MUJOCO_NSTATE values).
//
// Built two ways from this one file:
//   - as a plugin library (-DHYST_MUJOCO_LIBRARY, linked with libmujoco and libhyst): it
//     registers both plugins when loaded, as MuJoCo's own plugin libraries do;
//   - into hyst's Python extension (crates/hyst-py/build.rs): `hyst.mujoco.load()` passes the
//     functions of the libmujoco that the `mujoco` package loaded to `hyst_mujoco_register`.
// Either way the MuJoCo functions are called through `hyst_mujoco_api`, and registration
// refuses a libmujoco whose version differs from the headers this file was compiled with.

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mujoco/mujoco.h>

#include "hyst.h"
#include "hyst_mujoco.h"

// Per actuator: the memory of Definition 2.1 in act, in this order.
enum { ACT_HAS_HISTORY, ACT_DIRECTION, ACT_REVERSAL_INPUT, ACT_REVERSAL_OUTPUT, ACT_LAST_INPUT,
       ACT_LAST_OUTPUT };
// Per actuator in plugin_state: the new memory (as in act), then the target.
enum { STATE_TARGET = HYST_MUJOCO_ACTDIM };

static hyst_mujoco_api mj;

static const char *const ATTRIBUTES[] = {"k1", "k2", "kp", "kv", "model"};
enum { N_ATTRIBUTES = sizeof ATTRIBUTES / sizeof ATTRIBUTES[0] };

// One actuator of an instance: its operator, or its own copy of the model file's model.
typedef struct {
  int id;
  hyst_operator op;
  struct hyst_model *model;
} unit;

typedef struct {
  const char *name;  // the plugin's name, for messages
  int inverse;       // hyst.compensator
  double kp, kv;
  int nunit;
  unit *units;
  int warned;        // a refused sample was reported once
} instance;

// The instance's config value `key` as a number into *value: 1 read, 0 absent, -1 refused
// (warned).
static int config_number(const mjModel *m, int id, const char *plugin, const char *key,
                         double *value) {
  const char *text = mj.get_plugin_config(m, id, key);
  if (text == NULL || text[0] == '\0') {
    return 0;
  }
  char *end = NULL;
  errno = 0;
  double v = strtod(text, &end);
  while (end != NULL && (*end == ' ' || *end == '\t')) {
    end++;
  }
  if (end == text || end == NULL || *end != '\0' || errno != 0 || !isfinite(v)) {
    mj.warning("%s: config %s = \"%s\" is not a finite number", plugin, key, text);
    return -1;
  }
  *value = v;
  return 1;
}

// The memory that `act` holds. The two flags are read by rounding, so that the small
// perturbations of finite differences (mjd_transitionFD) leave them as they are.
static void memory_from_act(const mjtNum *act, hyst_memory *memory) {
  memory->has_history = act[ACT_HAS_HISTORY] > 0.5;
  memory->direction = act[ACT_DIRECTION] < 0 ? -1 : 1;
  memory->reversal_input = act[ACT_REVERSAL_INPUT];
  memory->reversal_output = act[ACT_REVERSAL_OUTPUT];
  memory->last_input = act[ACT_LAST_INPUT];
  memory->last_output = act[ACT_LAST_OUTPUT];
}

static void memory_to(const hyst_memory *memory, mjtNum *out) {
  out[ACT_HAS_HISTORY] = memory->has_history;
  out[ACT_DIRECTION] = memory->has_history ? memory->direction : 0;
  out[ACT_REVERSAL_INPUT] = memory->has_history ? memory->reversal_input : 0;
  out[ACT_REVERSAL_OUTPUT] = memory->has_history ? memory->reversal_output : 0;
  out[ACT_LAST_INPUT] = memory->has_history ? memory->last_input : 0;
  out[ACT_LAST_OUTPUT] = memory->has_history ? memory->last_output : 0;
}

static int same_memory(const hyst_memory *a, const hyst_memory *b) {
  if (a->has_history != b->has_history) {
    return 0;
  }
  return a->has_history == 0 ||
         (a->direction == b->direction && a->reversal_input == b->reversal_input &&
          a->reversal_output == b->reversal_output && a->last_input == b->last_input &&
          a->last_output == b->last_output);
}

// One sample of actuator `u` from the memory in `act` and `ctrl`: the new memory and the target
// into `state`. Returns a hyst status; on an error `state` keeps the memory of `act` and the
// last target.
static int32_t step(instance *in, unit *u, const mjtNum *act, double ctrl, mjtNum *state) {
  hyst_memory memory, held;
  memory_from_act(act, &memory);
  double target = 0.0;
  int32_t status;
  if (u->model != NULL) {
    // Set the model's run only when it is not already there (a restored or reset state): the
    // run that wrote this act holds it.
    status = hyst_model_get_memory(u->model, in->inverse, &held);
    if (status == HYST_OK && !same_memory(&held, &memory)) {
      status = hyst_model_set_memory(u->model, in->inverse, &memory);
    }
    if (status == HYST_OK) {
      status = hyst_model_process(u->model, in->inverse, &ctrl, &target, 1);
    }
    if (status == HYST_OK) {
      status = hyst_model_get_memory(u->model, in->inverse, &held);
    }
  } else {
    status = hyst_operator_set_memory(&u->op, &memory);
    if (status == HYST_OK) {
      status = hyst_operator_step(&u->op, ctrl, &target);
    }
    if (status == HYST_OK) {
      status = hyst_operator_get_memory(&u->op, &held);
    }
  }
  if (status != HYST_OK) {
    memory_to(&memory, state);
    return status;
  }
  memory_to(&held, state);
  state[STATE_TARGET] = target;
  return HYST_OK;
}

// Whether actuator `id` is disabled (its activations then stay as they are).
static int disabled(const mjModel *m, int id) {
  if (m->opt.disableflags & mjDSBL_ACTUATION) {
    return 1;
  }
  int group = m->actuator_group[id];
  return group >= 0 && group <= 30 && (m->opt.disableactuator & (1 << group));
}

static void act_dot(const mjModel *m, mjData *d, int id) {
  instance *in = (instance *)d->plugin_data[id];
  mjtNum *state = d->plugin_state + m->plugin_stateadr[id];
  for (int k = 0; k < in->nunit; k++) {
    int a = in->units[k].id;
    const mjtNum *act = d->act + m->actuator_actadr[a];
    mjtNum *s = state + k * HYST_MUJOCO_NSTATE;
    double ctrl = d->ctrl[a];
    if (m->actuator_ctrllimited[a]) {
      ctrl = fmin(fmax(ctrl, m->actuator_ctrlrange[2 * a]), m->actuator_ctrlrange[2 * a + 1]);
    }
    int32_t status = step(in, &in->units[k], act, ctrl, s);
    if (status != HYST_OK && !in->warned) {
      in->warned = 1;
      mj.warning("%s: actuator %d refused ctrl = %g (%s); its target holds (reported once)",
                 in->name, a, ctrl, hyst_status_message(status));
    }
    for (int j = 0; j < HYST_MUJOCO_ACTDIM; j++) {
      d->act_dot[m->actuator_actadr[a] + j] = (s[j] - act[j]) / m->opt.timestep;
    }
  }
}

static void compute(const mjModel *m, mjData *d, int id, int capability) {
  (void)capability;
  instance *in = (instance *)d->plugin_data[id];
  const mjtNum *state = d->plugin_state + m->plugin_stateadr[id];
  for (int k = 0; k < in->nunit; k++) {
    int a = in->units[k].id;
    double target = state[k * HYST_MUJOCO_NSTATE + STATE_TARGET];
    d->actuator_force[a] =
        in->kp * (target - d->actuator_length[a]) - in->kv * d->actuator_velocity[a];
  }
}

// After MuJoCo integrated act with act_dot: the new memory, exactly.
static void advance(const mjModel *m, mjData *d, int id) {
  instance *in = (instance *)d->plugin_data[id];
  const mjtNum *state = d->plugin_state + m->plugin_stateadr[id];
  for (int k = 0; k < in->nunit; k++) {
    int a = in->units[k].id;
    if (disabled(m, a)) {
      continue;
    }
    memcpy(d->act + m->actuator_actadr[a], state + k * HYST_MUJOCO_NSTATE,
           HYST_MUJOCO_ACTDIM * sizeof(mjtNum));
  }
}

static int nstate(const mjModel *m, int id) {
  int n = 0;
  for (int a = 0; a < m->nu; a++) {
    n += m->actuator_plugin[a] == id;
  }
  return n * HYST_MUJOCO_NSTATE;
}

static void destroy(mjData *d, int id) {
  instance *in = (instance *)d->plugin_data[id];
  if (in != NULL) {
    for (int k = 0; k < in->nunit; k++) {
      hyst_model_free(in->units[k].model);
    }
    free(in->units);
    free(in);
  }
  d->plugin_data[id] = 0;
}

static void reset(const mjModel *m, mjtNum *plugin_state, void *plugin_data, int id) {
  (void)plugin_data;
  memset(plugin_state, 0, (size_t)nstate(m, id) * sizeof(mjtNum));
}

// Checks the model and the config of instance `id` and sets its units; 0 or -1 (warned).
static int configure(const mjModel *m, int id, instance *in) {
  const char *name = in->name;
  if (m->opt.integrator == mjINT_RK4) {
    mj.warning("%s: the RK4 integrator evaluates actuators at intermediate states, which an "
               "operator with memory cannot take: use Euler, implicit or implicitfast", name);
    return -1;
  }
  double k1 = 0, k2 = 0;
  int has_k1 = config_number(m, id, name, "k1", &k1);
  int has_k2 = config_number(m, id, name, "k2", &k2);
  int has_kp = config_number(m, id, name, "kp", &in->kp);
  int has_kv = config_number(m, id, name, "kv", &in->kv);
  if (has_k1 < 0 || has_k2 < 0 || has_kp < 0 || has_kv < 0) {
    return -1;
  }
  if (has_kp == 0 || !(in->kp > 0)) {
    mj.warning("%s: config kp (the servo's stiffness, force per unit length) must be given and "
               "> 0", name);
    return -1;
  }
  if (has_kv == 0) {
    in->kv = 0;
  } else if (in->kv < 0) {
    mj.warning("%s: config kv = %g must be >= 0", name, in->kv);
    return -1;
  }
  const char *path = mj.get_plugin_config(m, id, "model");
  int has_model = path != NULL && path[0] != '\0';
  if (has_model ? (has_k1 || has_k2) : !(has_k1 && has_k2)) {
    mj.warning("%s: give either k1 and k2 (the operator H(k1, k2)) or model (a model file), "
               "not both", name);
    return -1;
  }
  for (int a = 0; a < m->nu; a++) {
    if (m->actuator_plugin[a] != id) {
      continue;
    }
    if (m->actuator_actnum[a] != HYST_MUJOCO_ACTDIM) {
      mj.warning("%s: actuator %d has actdim %d; the operator's memory takes %d: add "
                 "actdim=\"%d\" to the actuator's plugin element", name, a,
                 m->actuator_actnum[a], HYST_MUJOCO_ACTDIM, HYST_MUJOCO_ACTDIM);
      return -1;
    }
    if (m->actuator_dyntype[a] != mjDYN_NONE || m->actuator_actlimited[a]) {
      mj.warning("%s: actuator %d: its activations hold the operator's memory, so it takes no "
                 "dyntype and no actrange", name, a);
      return -1;
    }
    unit *u = &in->units[in->nunit++];
    u->id = a;
    u->model = NULL;
    if (has_model) {
      char error[512];
      u->model = hyst_model_load(path, error, sizeof error);
      if (u->model == NULL) {
        mj.warning("%s: %s", name, error);
        return -1;
      }
      // hyst_model_load refused a model with dynamics or a rate term, with its reason; what
      // has no memory of Definition 2.1 to keep in act now is a Prandtl-Ishlinskii model.
      hyst_memory probe;
      if (hyst_model_get_memory(u->model, in->inverse, &probe) != HYST_OK) {
        mj.warning("%s: model %s is a Prandtl-Ishlinskii model, whose memory (its plays) the "
                   "activations do not hold: fit the smooth model (hyst fit --model-kind smooth)",
                   name, path);
        return -1;
      }
    } else {
      int32_t status = in->inverse ? hyst_operator_init_inverse(&u->op, k1, k2)
                                   : hyst_operator_init_direct(&u->op, k1, k2);
      if (status != HYST_OK) {
        mj.warning("%s: k1 = %g, k2 = %g: %s", name, k1, k2, hyst_status_message(status));
        return -1;
      }
    }
  }
  if (in->nunit == 0) {
    mj.warning("%s: instance %d drives no actuator", name, id);
    return -1;
  }
  return 0;
}

static int init(const mjModel *m, mjData *d, int id, const char *name, int inverse) {
  instance *in = calloc(1, sizeof *in);
  unit *units = calloc((size_t)(m->nu > 0 ? m->nu : 1), sizeof *units);
  if (in == NULL || units == NULL) {
    free(in);
    free(units);
    mj.warning("%s: out of memory", name);
    return -1;
  }
  in->name = name;
  in->inverse = inverse;
  in->units = units;
  d->plugin_data[id] = (uintptr_t)in;
  if (configure(m, id, in) != 0) {
    destroy(d, id);
    return -1;
  }
  return 0;
}

static int init_backlash(const mjModel *m, mjData *d, int id) {
  return init(m, d, id, "hyst.backlash", 0);
}

static int init_compensator(const mjModel *m, mjData *d, int id) {
  return init(m, d, id, "hyst.compensator", 1);
}

static void define(mjpPlugin *plugin, const char *name, int (*init_fn)(const mjModel *, mjData *,
                                                                        int)) {
  mj.default_plugin(plugin);
  plugin->name = name;
  plugin->capabilityflags |= mjPLUGIN_ACTUATOR;
  plugin->nattribute = N_ATTRIBUTES;
  plugin->attributes = ATTRIBUTES;
  plugin->nstate = nstate;
  plugin->init = init_fn;
  plugin->destroy = destroy;
  plugin->reset = reset;
  plugin->actuator_act_dot = act_dot;
  plugin->compute = compute;
  plugin->advance = advance;
}

int hyst_mujoco_register(const hyst_mujoco_api *api, char *error, size_t error_len) {
  if (api == NULL || api->get_plugin_config == NULL || api->warning == NULL ||
      api->default_plugin == NULL || api->register_plugin == NULL || api->version == NULL) {
    snprintf(error, error_len, "hyst_mujoco_register: a MuJoCo function is missing");
    return -1;
  }
  int version = api->version();
  if (version != mjVERSION_HEADER) {
    snprintf(error, error_len,
             "the hyst MuJoCo plugins were built against MuJoCo %d.%d.%d, and the libmujoco "
             "loaded is %d.%d.%d: MuJoCo plugins work only with the version they were built "
             "against (install mujoco==%d.%d.%d, or rebuild hyst against this MuJoCo)",
             mjVERSION_HEADER / 1000000, mjVERSION_HEADER / 1000 % 1000,
             mjVERSION_HEADER % 1000, version / 1000000, version / 1000 % 1000, version % 1000,
             mjVERSION_HEADER / 1000000, mjVERSION_HEADER / 1000 % 1000,
             mjVERSION_HEADER % 1000);
    return -1;
  }
  mj = *api;
  mjpPlugin backlash, compensator;
  define(&backlash, "hyst.backlash", init_backlash);
  define(&compensator, "hyst.compensator", init_compensator);
  // MuJoCo ignores a plugin registered again with the same definition.
  mj.register_plugin(&backlash);
  mj.register_plugin(&compensator);
  return 0;
}

#ifdef HYST_MUJOCO_LIBRARY
mjPLUGIN_LIB_INIT(hyst_mujoco) {
  hyst_mujoco_api api = {mj_getPluginConfig, mju_warning, mjp_defaultPlugin,
                         mjp_registerPlugin, mj_version};
  char error[512];
  if (hyst_mujoco_register(&api, error, sizeof error) != 0) {
    mju_warning("%s", error);
  }
}
#endif
