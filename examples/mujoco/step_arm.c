// Steps an MJCF that uses hyst's MuJoCo actuator plugins from C (docs/mujoco.md):
//
//   step_arm PLUGIN_LIBRARY MODEL.xml < ctrl.txt > targets.txt
//
// loads the plugin library (libhyst_mujoco.so, built as docs/mujoco.md shows), then the MJCF,
// and for each ctrl value on stdin (one per line) sets the first actuator's ctrl, calls
// mj_step and prints the step's target (the actuator's plugin state holds it last) with 17
// significant digits: the values `hyst run` gives for the same samples.
#include <stdio.h>
#include <stdlib.h>

#include <mujoco/mujoco.h>

#include "hyst_mujoco.h"

int main(int argc, char **argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: %s PLUGIN_LIBRARY MODEL.xml < ctrl.txt\n", argv[0]);
    return 2;
  }
  mj_loadPluginLibrary(argv[1]);
  char error[1000] = "";
  mjModel *m = mj_loadXML(argv[2], NULL, error, sizeof error);
  if (m == NULL) {
    fprintf(stderr, "%s: %s\n", argv[2], error);
    return 1;
  }
  mjData *d = mj_makeData(m);
  if (d == NULL || m->nu < 1 || m->nplugin < 1) {
    fprintf(stderr, "%s: no data, or no actuator plugin\n", argv[2]);
    mj_deleteModel(m);
    return 1;
  }
  int target = m->plugin_stateadr[0] + HYST_MUJOCO_NSTATE - 1;
  double ctrl;
  while (scanf("%lf", &ctrl) == 1) {
    d->ctrl[0] = ctrl;
    mj_step(m, d);
    printf("%.17g\n", d->plugin_state[target]);
  }
  mj_deleteData(d);
  mj_deleteModel(m);
  return 0;
}
