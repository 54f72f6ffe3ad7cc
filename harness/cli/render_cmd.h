/* render_cmd.h: `accelbench render`. */
#ifndef ACCELBENCH_RENDER_CMD_H
#define ACCELBENCH_RENDER_CMD_H

#include "../run/run_options.h"

/* `accelbench render`: a Whitted image (point-light shadows, mirror
 * reflection to depth 3) or, with --heatmap, a per-pixel cost image of the
 * primary rays. Returns the exit status. */
int render_main(options *o);

#endif
