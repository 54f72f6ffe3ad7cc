/* bsp_kaplan_jansen.h: the test accessor of `bsp` (bsp_kaplan_jansen.c). */
#ifndef ACCELBENCH_BSP_KAPLAN_JANSEN_H
#define ACCELBENCH_BSP_KAPLAN_JANSEN_H

#include "../accel.h"
#include "kd_tree.h"

/* The tree of a built `bsp` (never used while tracing). */
const kd_tree *bsp_debug_tree(const accel *a);

#endif
