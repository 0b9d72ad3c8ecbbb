/* env_light_groups.c - building the groups of env_light_groups.h: per map, its lights' mean
 * direction, the cone about it that holds them, and their linear sum. */
#include "env_light_groups.h"

#include <math.h>

void sl_env_light_groups_build(sl_env_light_groups *g, const vec4 *dir, const vec4 *radiance, int count,
                               const signed char *map_of_light, int maps)
{
    int members = 0;
    g->count = 0;
    for (int k = 0; k <= maps; k++) {
        int map = k < maps ? k : -1; /* the uncovered lights last */
        sl_env_light_group *e = &g->group[g->count];
        *e = (sl_env_light_group){.first = members};
        vec3 sum = vec3s(0.0f);
        for (int j = 0; j < count; j++) {
            if (map_of_light[j] != map)
                continue;
            vec3 l = xyz(dir[j]), L = xyz(radiance[j]);
            g->member[members++] = (unsigned char)j;
            sum = add(sum, l);
            e->mr = add(e->mr, scale(l, L.x));
            e->mg = add(e->mg, scale(l, L.y));
            e->mb = add(e->mb, scale(l, L.z));
        }
        e->count = members - e->first;
        if (e->count == 0)
            continue;
        float len = length(sum);
        e->axis = len > 0.0f ? scale(sum, 1.0f / len) : vec3(0.0f, 0.0f, 1.0f);
        float cos_min = 1.0f;
        for (int i = e->first; i < members; i++)
            cos_min = fminf(cos_min, dot(xyz(dir[g->member[i]]), e->axis));
        /* a margin over the float rounding of N.l near 0, where the linear sum and the clamped one
         * part; a cone of 90 degrees or more has no side that sees all or none of it */
        e->sin_spread = cos_min > 0.0f ? sqrtf(1.0f - cos_min * cos_min) + 1e-4f : 2.0f;
        g->count++;
    }
}
