/* env_light_groups.h - the env lights grouped by the shadow map that covers them, so that their
 * part of the irradiance, sum L_k max(N.l_k, 0), costs a few dot products a map rather than one a
 * light (the batched path's env_shadow_diffuse; the port and lighting.frag loop over the lights).
 *
 * A group's lights lie within a cone about `axis`: where N.axis >= sin_spread every light is
 * above the surface's horizon and the sum is linear, M N with M = sum L_k l_k^T (rows mr, mg,
 * mb); where N.axis <= -sin_spread every light is below it and the sum is 0; only the band
 * between loops over the lights. The same sum as the loop's, in another order (float rounding
 * apart). With clusters of a few degrees (src/shadow) the band is a few degrees wide. */
#ifndef SL_ENV_LIGHT_GROUPS_H
#define SL_ENV_LIGHT_GROUPS_H

#include <softlight/glsl.h>

#include "../ibl/env_lights.h"
#include "../shadow/shadow.h"

typedef struct {
    vec3 axis;         /* unit, environment space */
    float sin_spread;  /* sin of the widest angle from the axis to a light, plus a margin; 2: no cone */
    vec3 mr, mg, mb;   /* sum over the lights of radiance.{r,g,b} times direction */
    int first, count;  /* the lights: member[first .. first + count - 1] */
} sl_env_light_group;

typedef struct {
    int count;                                  /* groups: the maps' that cover a light, then the uncovered lights' */
    sl_env_light_group group[SL_SHADOW_SUN_MAX + 1];
    unsigned char member[SL_ENV_LIGHTS_MAX];    /* light indices, group after group */
} sl_env_light_groups;

/* Group lights 0 .. count - 1 (dir: unit directions, radiance: times the node weight, as the
 * lighting uniforms hold them) by map_of_light[j] (0 .. maps - 1, or -1: no map). */
void sl_env_light_groups_build(sl_env_light_groups *g, const vec4 *dir, const vec4 *radiance, int count,
                               const signed char *map_of_light, int maps);

/* Group k's part of the irradiance about unit N: sum over its lights of L_k max(N.l_k, 0). */
static inline vec3 sl_env_light_group_irradiance(const sl_env_light_groups *g, int k, const vec4 *dir,
                                                 const vec4 *radiance, vec3 N)
{
    const sl_env_light_group *e = &g->group[k];
    float na = dot(N, e->axis);
    if (na >= e->sin_spread)
        return vec3(dot(e->mr, N), dot(e->mg, N), dot(e->mb, N));
    vec3 sum = vec3s(0.0f);
    if (na <= -e->sin_spread)
        return sum;
    for (int i = e->first; i < e->first + e->count; i++) {
        int j = g->member[i];
        float c = maxf(dot(xyz(dir[j]), N), 0.0f);
        sum = add(sum, scale(xyz(radiance[j]), c));
    }
    return sum;
}

#endif
