// MuJoCo actuator plugins over hyst's C API: hyst.backlash and hyst.compensator
// (hyst_mujoco.c, docs/mujoco.md).
#ifndef HYST_MUJOCO_H
#define HYST_MUJOCO_H

#include <stddef.h>

#include <mujoco/mujoco.h>

#ifdef __cplusplus
extern "C" {
#endif

// The activations of each actuator (its `actdim`): the memory of Definition 2.1, in this
// order: has_history (0 or 1), direction (±1), reversal input α0, reversal output β0, last
// input, last output; all 0 is an operator with no history.
#define HYST_MUJOCO_ACTDIM 6
// The plugin state of each actuator: the memory of the last step (as in act), then its target.
#define HYST_MUJOCO_NSTATE (HYST_MUJOCO_ACTDIM + 1)

// The MuJoCo functions the plugins call, from the libmujoco they run in.
typedef struct hyst_mujoco_api {
  const char *(*get_plugin_config)(const mjModel *m, int plugin_id, const char *attrib);
  void (*warning)(const char *msg, ...);
  void (*default_plugin)(mjpPlugin *plugin);
  int (*register_plugin)(const mjpPlugin *plugin);
  int (*version)(void);
} hyst_mujoco_api;

// Registers hyst.backlash and hyst.compensator with the MuJoCo whose functions `api` holds.
// Returns 0, or -1 with the reason in `error` (`error_len` bytes, NUL-terminated) when a
// function is missing or that MuJoCo's version (`api->version()`) is not the version of the
// headers this file was compiled with (mjVERSION_HEADER): plugins work only with that one.
// Registering again is harmless.
int hyst_mujoco_register(const hyst_mujoco_api *api, char *error, size_t error_len);

#ifdef __cplusplus
}
#endif

#endif  // HYST_MUJOCO_H
