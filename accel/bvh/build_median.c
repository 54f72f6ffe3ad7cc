/* build_median.c: the object-median builder (bvh.h). Each node of more
 * than max_leaf primitives is cut at the median of its centroids along the
 * longest axis of their bounds, so the tree is balanced: depth
 * ceil(log2(n / max_leaf)), whatever the geometry. It ignores sizes and
 * empty space (the SAH builder does not), which is why it is the baseline
 * of the builders. */
#include "build.h"

static uint32_t median_split(uint32_t *ids, uint32_t n, box3 box, const box3 *boxes, const vec3 *centroids,
                             const bvh_config *cfg, bvh_split_sides *sides)
{
    (void)box, (void)boxes, (void)sides;
    if (n <= cfg->max_leaf) return 0;
    vec3 e = box_extent(bvh_centroid_bounds(ids, n, centroids));
    int axis = e.x >= e.y && e.x >= e.z ? 0 : e.y >= e.z ? 1 : 2;
    bvh_select(ids, n, n / 2, centroids, axis);
    return n / 2;
}

int bvh_build_median(bvh_t *b, const box3 *boxes, const vec3 *centroids, uint32_t n, const bvh_config *cfg)
{
    return bvh_build_topdown(b, boxes, centroids, n, cfg, median_split);
}
