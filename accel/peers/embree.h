/* embree.h: the one thing beyond accel_ops that embree.c exports: its
 * RTCScene, so the overhead benchmark can call rtcIntersect1 on exactly the
 * structure the harness traces. */
#ifndef ACCELBENCH_EMBREE_H
#define ACCELBENCH_EMBREE_H

#include <embree3/rtcore.h>
#include "../accel.h"

RTCScene embree_scene_of(accel *a);

#endif
