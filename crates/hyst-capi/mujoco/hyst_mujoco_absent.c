// hyst_mujoco_register of a Python extension built without MuJoCo's headers
// (crates/hyst-py/build.rs compiles this file instead of hyst_mujoco.c): there are no plugins
// to register, and it says so. Same signature as hyst_mujoco.h's, whose MuJoCo types this file
// cannot name.
#include <stddef.h>
#include <string.h>

int hyst_mujoco_register(const void *api, char *error, size_t error_len);

int hyst_mujoco_register(const void *api, char *error, size_t error_len) {
  static const char reason[] =
      "this hyst was built without MuJoCo's headers, so it has no MuJoCo plugins: reinstall "
      "it on Python >= 3.11 (which MuJoCo 4 needs), where the build gets them "
      "(pip install \"./crates/hyst-py[mujoco]\", docs/mujoco.md)";
  (void)api;
  if (error != NULL && error_len > 0) {
    size_t n = strlen(reason);
    if (n >= error_len) n = error_len - 1;
    memcpy(error, reason, n);
    error[n] = '\0';
  }
  return -1;
}
