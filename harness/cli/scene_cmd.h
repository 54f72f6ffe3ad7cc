/* scene_cmd.h: `accelbench scene info|export`. */
#ifndef ACCELBENCH_SCENE_CMD_H
#define ACCELBENCH_SCENE_CMD_H

/* argv[0] is "scene". Returns the exit status (0, or 2 on bad input). */
int scene_cmd_main(int argc, char **argv);

#endif
